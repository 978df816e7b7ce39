"""Far trees as impostor cards (trees/_impostor_bake.py, shaders/trees/impostor.glsl): the atlas's
layout, the card's shading against its numpy twin (trees/_impostor_atlas.py), the cross-fade from the
mesh along a path, the cards in the shadow maps and the atlas's cache."""

from dataclasses import replace

import moderngl
import numpy as np
import pytest

from cityshade import trees
from cityshade.errors import UsageError
from cityshade.frame import Daylight
from cityshade.gl import ProgramCache, RenderTarget
from cityshade.render.testing import CascadedShadows
from cityshade.scene import Camera
from cityshade.trees import EVERY_FRAME, FRAME_PIXELS, FRAMES, Light, TreeSettings, impostor_twin
from trees_scene import SIZE, one_tree, render, save, write_frame_block

ONLY_IMPOSTORS = (1e6, 0.9e6)  # impostor_rows: every tree spans fewer rows, so is wholly its impostor
NO_IMPOSTORS = (1e-3, 0.9e-3)  # every tree spans more


@pytest.fixture(scope="module")
def programs(gl_context):
    return ProgramCache(gl_context)


def test_frames_and_normals_round_trip():
    frames = np.stack(np.meshgrid(range(FRAMES), range(FRAMES), indexing="ij"), axis=-1).reshape(-1, 2)
    assert np.array_equal(trees.frame_of(trees.frame_direction(frames)), frames)
    uv = np.random.default_rng(1).uniform(0, 1, (500, 2))
    assert np.allclose(trees.hemi_octahedral(trees.hemi_octahedral_direction(uv)), uv, atol=1e-12)
    for d in trees.frame_direction(frames):
        right, up = trees.frame_basis(d)
        assert np.allclose(np.cross(right, up), d) and abs(right[1]) < 1e-12  # no roll: right stays level
    n = np.random.default_rng(2).normal(size=(500, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    assert np.allclose(trees.octahedral_normal_decode(trees.octahedral_normal(n)), n, atol=1e-12)


TWIN_SIZE = (256, 256)


def _draw_cards(ctx, tree, camera, daylight, focal_rows=100.0):
    """The impostor cards alone, alpha-tested, no MSAA, no shadows: (H, W, 4) float32, top row first."""
    write_frame_block(ctx, camera, daylight)
    tree.prepare(camera.eye, focal_rows=focal_rows)
    target = RenderTarget(ctx, TWIN_SIZE, (("f4", 4),))
    target.use()
    target.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    tree.draw({"u_view_proj": camera.view_projection(1.0)}, camera.view(), None, parts=("impostors",))
    image = target.read().astype(np.float32)
    target.release()
    return image


VIEWS = {  # from below the crown's centre (the frames clamp to the horizon), level, and from above
    "street": Camera((7.0, 1.7, 14.0), (0.0, 5.0, 0.0), fov_y=60, near=0.5, far=500),
    "level": Camera((-10.0, 5.5, 12.0), (0.0, 5.0, 0.0), fov_y=60, near=0.5, far=500),
    "aerial": Camera((8.0, 20.0, 10.0), (0.0, 4.0, 0.0), fov_y=60, near=0.5, far=500),
}


@pytest.mark.parametrize("species", ["oak", "fir"])
@pytest.mark.parametrize("view", sorted(VIEWS))
def test_impostor_card_matches_the_numpy_twin(gl_context, programs, species, view, output_dir):
    """A turned, scaled tree as its impostor card: the twin casts each pixel's ray onto the card of
    the nearest frame, samples the atlas bilinearly, alpha-tests and lights it. The pixels the card
    covers agree but for a few on the alpha-test edge; colours within 0.02. The views are near
    enough that a texel covers more than a pixel: the GPU samples the atlas's first level, as the
    twin does (farther, the mipmaps the GPU builds take over)."""
    tree = one_tree(gl_context, programs, species, alpha_to_coverage=False, impostor_rows=ONLY_IMPOSTORS)
    tree.trees["yaw"], tree.trees["scale"] = 0.7, 1.1
    camera, daylight = VIEWS[view], Daylight.at(16.0)
    try:
        gpu = _draw_cards(gl_context, tree, camera, daylight)
        impostor = tree.impostors[next(iter(tree.models))]
        centre = tree.trees["position"][0] + impostor.atlas.centre  # near enough for the texel size
        focal = TWIN_SIZE[1] / (2 * np.tan(np.radians(camera.fov_y) / 2))
        card_pixels = 2 * impostor.atlas.radius * 1.1 * focal / np.linalg.norm(camera.eye - centre)
        assert card_pixels > 1.2 * FRAME_PIXELS, card_pixels
        light = Light(daylight.sun_direction, daylight.sun_color, daylight.sky_ambient, daylight.ground_ambient)
        t = tree.trees[0]
        inverse = np.linalg.inv(camera.view_projection(1.0))
        expected, covered = impostor_twin(
            impostor.atlas,
            (*t["position"], t["yaw"]),
            t["scale"],
            camera.eye,
            inverse,
            TWIN_SIZE,
            light,
            tree.settings.specular_fade,
        )
    finally:
        tree.release()
    drawn = gpu[..., 3] > 0
    both = drawn & covered
    colour = np.abs(gpu[..., :3] - expected).max(axis=2)[both]
    print(
        f"{species} {view}: {covered.sum()} pixels in the twin, {np.count_nonzero(drawn != covered)} covered "
        f"differently, {np.count_nonzero(colour > 0.02)} colours off by more than 0.02 (max {colour.max():.4f})"
    )
    save(np.hstack([gpu[..., :3], expected]), f"impostor_twin_{species}_{view}", output_dir)
    assert covered.sum() > 2000
    assert np.count_nonzero(drawn != covered) <= 0.01 * covered.sum()
    assert np.count_nonzero(colour > 0.02) <= 0.005 * both.sum()


@pytest.mark.parametrize("samples", [4, 0])
def test_mesh_to_impostor_cross_fade_has_no_pop_along_a_path(gl_context, programs, samples, output_dir):
    """A tree passing through the mesh-to-impostor band in 20 steps (the band, in image rows, slid
    past it: only the representation changes, not the view): no step between consecutive frames
    carries more than 40% of the whole change. The control, a band narrower than a step (a hard
    switch), puts all of it into one step. The fade curves do not overlap (trees.lod_alphas with
    overlap 0): with the offset curves of the mesh LODs, mid-band both had 3 of 4 samples, the same
    three, and the sky showed through a quarter of the tree for a frame. With 4x MSAA the fade is
    alpha to coverage; without (the viewer's default), the fizzle's dither."""
    tree = one_tree(gl_context, programs, "oak", shadows=False, fins=False)
    height = tree.models[next(iter(tree.models))].height
    camera = Camera((0, 6.0, 120.0), (0, 6.0, 0), fov_y=10, near=0.5, far=400)
    focal = SIZE[1] / (2 * np.tan(np.radians(camera.fov_y) / 2))
    metres_per_row = 120.0 / (height * focal)  # the band is linear in this
    steps, band = 20, 0.4 * metres_per_row

    def path(width: float) -> list[np.ndarray]:
        frames = []
        for k in range(steps + 1):
            # the hard switch's narrow band sits between two steps, not on one
            start = metres_per_row - k / steps * band + ((band - width) / 2 + band / steps / 2) * (width < band)
            tree.settings = replace(tree.settings, impostor_rows=(1 / start, 1 / (start + width)))
            frames.append(render(gl_context, tree, camera, samples=samples, focal_rows=focal))
        return frames

    jumps = {}
    for name, width in (("cross-fade", band), ("hard switch", band / 100)):
        frames = path(width)
        total = np.abs(frames[-1] - frames[0]).mean()
        steps_taken = [np.abs(b - a).mean() / total for a, b in zip(frames, frames[1:])]
        print(name, np.round(steps_taken, 3))
        jumps[name] = max(steps_taken)
        assert total > 1e-4, "the mesh and the impostor must differ somewhere"
        if name == "cross-fade":
            save(np.hstack([frames[0], frames[steps // 2], frames[-1]]), f"impostor_fade_path_{samples}x", output_dir)
    tree.release()
    print("largest step between frames, share of the whole mesh-to-impostor change:", jumps)
    assert jumps["cross-fade"] < 0.4
    assert jumps["hard switch"] > 0.9


def _shadow_coverage(ctx, tree, camera, focal) -> np.ndarray:
    """Which texels of the three cascades the tree's casters cover (every caster in each)."""
    daylight = Daylight.at(16.0)
    write_frame_block(ctx, camera, daylight)
    tree.prepare(camera.eye, focal_rows=focal)
    shadows = CascadedShadows(ctx, 256, shadow_far=150.0, rates=EVERY_FRAME)
    shadows.update(0, camera, 1.0, daylight.sun_direction, tree.draw_shadow)
    depth = np.concatenate([np.frombuffer(m.read(), np.float32) for m in shadows.maps])
    shadows.release()
    return depth < 1.0


def test_impostor_cards_cast_the_tree_s_shadow(gl_context, programs):
    """In the shadow pass the cards face the sun and are alpha-tested: the texels they cover in a
    cascade overlap those of the mesh's casters (trunks, leaves, fronds) by most of their union."""
    camera = Camera((0.0, 5.0, 45.0), (0.0, 5.0, 0.0), fov_y=40, near=0.5, far=500)
    covered = {}
    for name, rows in (("mesh", NO_IMPOSTORS), ("impostor", ONLY_IMPOSTORS)):
        tree = one_tree(gl_context, programs, "oak", impostor_rows=rows)
        covered[name] = _shadow_coverage(gl_context, tree, camera, focal=100.0)
        tree.release()
    union = covered["mesh"] | covered["impostor"]
    overlap = np.count_nonzero(covered["mesh"] & covered["impostor"]) / np.count_nonzero(union)
    print(f"shadow texels: mesh {covered['mesh'].sum()}, cards {covered['impostor'].sum()}, overlap {overlap:.2f}")
    assert covered["mesh"].sum() > 100
    assert overlap > 0.6


def test_a_second_pass_reads_the_atlas_baked_by_the_first(gl_context, programs, monkeypatch):
    """The atlas is baked once: a pass made afterwards (its process memory emptied) reads the same
    arrays back from the cache on disk without drawing anything."""
    from cityshade.trees import _tree_pass as _trees

    first = one_tree(gl_context, programs, "poplar", impostor_rows=ONLY_IMPOSTORS)
    atlas = first.impostor(next(iter(first.models))).atlas
    first.release()
    monkeypatch.setattr(_trees, "_ATLASES", {})
    monkeypatch.setattr(_trees.TreePass, "_bake", lambda *a: pytest.fail("baked again"))
    second = one_tree(gl_context, programs, "poplar", impostor_rows=ONLY_IMPOSTORS)
    again = second.impostor(next(iter(second.models))).atlas
    second.release()
    assert np.array_equal(atlas.color, again.color) and np.array_equal(atlas.surface, again.surface)


@pytest.mark.parametrize("rows", [(49.0, 70.0), (70.0, 70.0), (70.0, 0.0), (70.0, -5.0)])
def test_impostor_rows_out_of_order_refused_in_one_line(rows):
    with pytest.raises(UsageError) as refused:
        TreeSettings(impostor_rows=rows)
    assert "\n" not in str(refused.value) and repr(rows) in str(refused.value)
