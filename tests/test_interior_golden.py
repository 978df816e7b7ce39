"""Golden images of interior mapping's validation scene, compared with a tolerance.

Regenerate on purpose with CITYSHADE_UPDATE_GOLDEN=1, then look at tests/golden/interior/*.png
(the renders of each run are in tests/output/).
"""

from pathlib import Path

import pytest
from PIL import Image

from cityshade.render import Renderer, RenderSettings
from cityshade.scene import make_city
from golden_images import check_golden

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
    check_golden(image, path)
