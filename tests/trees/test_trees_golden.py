"""Golden images of one tree, with every technique on and with each one off in turn, seen whole
and (for the bark relief, which covers few pixels of the whole tree) as a close-up of the trunk.

Compared with a block-local tolerance (golden_images); regenerate on purpose with
CITYSHADE_UPDATE_GOLDEN=1 (then look at them: tests/golden/trees/*.png, and the renders beside
them in tests/output/). Every golden must reject the render with its guarded technique switched.
"""

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade.gl import ProgramCache
from cityshade.render.testing import CascadedShadows
from cityshade.scene import Camera
from golden_images import check_golden, check_golden_rejects
from trees_scene import display, one_tree, render

GOLDEN = Path(__file__).parents[1] / "golden" / "trees"
VARIANTS = {
    "all": {},
    "no_fins": {"fins": False},
    "no_relief": {"relief": False},
    "alpha_test": {"alpha_to_coverage": False},
    "no_self_shadow": {"self_shadow": False},
    "one_sided": {"two_sided": False},
}
VIEWS = {
    "": Camera((1.2, 2.2, 3.2), (0.0, 2.6, 0.0), fov_y=60, near=0.05, far=100),
    "_trunk": Camera((0.7, 1.2, 0.9), (0.0, 1.2, 0.0), fov_y=50, near=0.05, far=100),
}
# golden (variant, view) -> the view in which that variant's technique shows
GOLDENS = [(variant, "") for variant in VARIANTS] + [("all", "_trunk"), ("no_relief", "_trunk")]
SHOWN_IN = {"no_relief": "_trunk"}
BACKGROUND = (0.45, 0.6, 0.8)


@pytest.fixture(scope="module")
def programs(gl_context):
    return ProgramCache(gl_context)


@pytest.fixture(scope="module")
def oak_image(gl_context, programs, output_dir):
    """The tree drawn with a variant's settings in a view, rendered once per module."""
    cache = {}

    def image(variant: str, view: str) -> np.ndarray:
        if (variant, view) not in cache:
            tree = one_tree(gl_context, programs, "oak", **VARIANTS[variant])
            shadows = CascadedShadows(gl_context, 512, shadow_far=40.0)
            hdr = render(gl_context, tree, VIEWS[view], shadows=shadows, background=BACKGROUND)
            tree.release()
            shadows.release()
            cache[variant, view] = display(hdr)
            Image.fromarray(cache[variant, view]).save(output_dir / f"trees_golden_{variant}{view}.png")
        return cache[variant, view]

    return image


@pytest.mark.parametrize("variant,view", GOLDENS)
def test_single_oak_matches_its_golden_image(oak_image, variant, view):
    check_golden(oak_image(variant, view), GOLDEN / f"oak_{variant}{view}.png")


@pytest.mark.parametrize("variant", [v for v in VARIANTS if v != "all"])
def test_goldens_reject_the_technique_switched(oak_image, variant):
    """The all-on golden rejects the tree with the technique off, and the technique-off golden
    rejects the all-on tree, in the view where the technique shows."""
    view = SHOWN_IN.get(variant, "")
    check_golden_rejects(oak_image(variant, view), GOLDEN / f"oak_all{view}.png", f"{variant} settings")
    check_golden_rejects(oak_image("all", view), GOLDEN / f"oak_{variant}{view}.png", "every technique on")


def test_goldens_reject_a_hole(oak_image):
    """A 12x12 black square in the middle of the tree must fail every tree golden."""
    for variant, view in GOLDENS:
        image = oak_image(variant, view).copy()
        h, w = image.shape[:2]
        image[h // 2 - 6 : h // 2 + 6, w // 2 - 6 : w // 2 + 6] = 0
        check_golden_rejects(image, GOLDEN / f"oak_{variant}{view}.png", "a 12x12 black hole")


@pytest.mark.parametrize("variant", [v for v in VARIANTS if v != "all"])
def test_each_technique_changes_the_picture(oak_image, variant):
    """Rendered now, on and off: the technique changes pixels of the tree (not the sky)."""
    view = SHOWN_IN.get(variant, "")
    on, off = oak_image("all", view).astype(int), oak_image(variant, view).astype(int)
    sky_colour = display(np.array([[BACKGROUND]], np.float32)).astype(int)[0, 0]
    sky = np.all(np.abs(on - sky_colour) <= 2, axis=2) & np.all(np.abs(off - sky_colour) <= 2, axis=2)
    changed = np.abs(on - off).max(axis=2)[~sky]
    assert (~sky).sum() > 500, "the tree covers too few pixels to judge"
    print(f"{variant}: {int((changed > 8).sum())} of {changed.size} tree pixels change by more than 8/255")
    assert (changed > 8).sum() >= 40, f"{variant}: switching the technique barely changes the tree"
