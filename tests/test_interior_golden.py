"""Golden images of interior mapping's validation scene, compared with a tolerance.

Regenerate on purpose with CITYSHADE_UPDATE_GOLDEN=1, then look at tests/golden/interior/*.png
(the renders of each run are in tests/output/).
"""

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade.render import Renderer, RenderSettings
from cityshade.scene import make_city

GOLDEN = Path(__file__).parent / "golden" / "interior"
VIEWS = ("corner", "cylinder", "dome")
SCENE = make_city("interior")


@pytest.fixture(scope="module")
def renderer(gl_context):
    r = Renderer((192, 128), RenderSettings(samples=0, lights=0.55, animation_time=0.5), ctx=gl_context)
    r.set_city(SCENE)
    yield r
    r.release()


@pytest.mark.parametrize("view", VIEWS)
def test_validation_views_match_their_golden_images(renderer, output_dir, view):
    image = renderer.render(SCENE.camera(view))
    Image.fromarray(image).save(output_dir / f"interior_golden_{view}.png")
    path = GOLDEN / f"{view}.png"
    if os.environ.get("CITYSHADE_UPDATE_GOLDEN"):
        GOLDEN.mkdir(parents=True, exist_ok=True)
        Image.fromarray(image).save(path)
    expected = np.asarray(Image.open(path)).astype(int)
    diff = np.abs(image.astype(int) - expected).max(axis=2)
    assert diff.mean() < 1.5, f"mean difference {diff.mean():.2f}/255"
    assert (diff > 24).mean() < 0.01, f"{(diff > 24).sum()} pixels differ by more than 24/255"
