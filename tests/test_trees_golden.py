"""Golden images of one tree, with every technique on and with each one off in turn.

Compared with a tolerance; regenerate on purpose with CITYSHADE_UPDATE_GOLDEN=1 (then look at them:
tests/golden/trees/*.png, and the renders beside them in tests/output/).
"""

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade.gl import ProgramCache
from cityshade.render._shadows import CascadedShadows
from cityshade.scene import Camera
from golden_images import check_golden
from trees_scene import display, one_tree, render

GOLDEN = Path(__file__).parent / "golden" / "trees"
VARIANTS = {
    "all": {},
    "no_fins": {"fins": False},
    "no_relief": {"relief": False},
    "alpha_test": {"alpha_to_coverage": False},
    "no_self_shadow": {"self_shadow": False},
    "one_sided": {"two_sided": False},
}


@pytest.fixture(scope="module")
def programs(gl_context):
    return ProgramCache(gl_context)


@pytest.mark.parametrize("variant", sorted(VARIANTS))
def test_single_oak_matches_its_golden_image(gl_context, programs, output_dir, variant):
    tree = one_tree(gl_context, programs, "oak", **VARIANTS[variant])
    shadows = CascadedShadows(gl_context, 512, shadow_far=40.0)
    camera = Camera((1.2, 2.2, 3.2), (0.0, 2.6, 0.0), fov_y=60, near=0.05, far=100)
    image = display(render(gl_context, tree, camera, shadows=shadows, background=(0.45, 0.6, 0.8)))
    tree.release()
    shadows.release()
    Image.fromarray(image).save(output_dir / f"trees_golden_{variant}.png")
    path = GOLDEN / f"oak_{variant}.png"
    check_golden(image, path)


def test_each_technique_changes_the_picture():
    images = {name: np.asarray(Image.open(GOLDEN / f"oak_{name}.png")).astype(int) for name in VARIANTS}
    for name in VARIANTS:
        if name != "all":
            assert np.abs(images[name] - images["all"]).max(axis=2).mean() > 0.1, name
