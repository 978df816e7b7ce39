"""The tree pass on the GPU: fins against their numpy twin, alpha to coverage, leaf shadows, LODs.

Images are small; every test that renders writes its picture to tests/output/ to be looked at.
"""

from dataclasses import replace

import moderngl
import numpy as np
import pytest
import shapely

from cityshade.frame import boxes_visible, frustum_planes
from cityshade.gl import FRAME_BLOCK, ProgramCache, RenderTarget, sampler_units, set_uniforms
from cityshade.render.testing import CascadedShadows
from cityshade.scene import Camera
from cityshade.trees import OAK, TreePass, extrude_fins, generate_tree, lod_alphas, tree_instances, vanish_alphas
from cityshade.trees.testing import INSTANCE_BYTES, PARTS
from trees_scene import SIZE, one_tree, render, render_ids, save


@pytest.fixture(scope="module")
def ctx(gl_context):
    return gl_context


@pytest.fixture(scope="module")
def programs(ctx):
    return ProgramCache(ctx)


def capture_fins(ctx, programs, positions, normals, eye, depth, fade=(1e6, 2e6)):
    """Runs the fin geometry shader with transform feedback; returns the emitted world positions."""
    program = programs.get("trees/fins.glsl", {"NO_SHADOWS": True}, varyings=("g_world", "g_w"))
    verts = np.zeros((len(positions) * 3, 13), np.float32)
    verts[:, 0:3] = positions.reshape(-1, 3)
    verts[:, 3:6] = normals.reshape(-1, 3)
    verts[:, 6:9] = np.cross(normals.reshape(-1, 3), [0.0, 1.0, 0.0]) + [1e-3, 0, 0]
    verts[:, 11] = 0.5
    instance = np.array([0, 0, 0, 0, 1, 1, 0, 0], np.float32)
    vbo, ibo = ctx.buffer(verts.tobytes()), ctx.buffer(instance.tobytes())
    layout, attributes = PARTS["fins"][1], PARTS["fins"][2]
    fmt = " ".join(f if a in program else f"{int(f[:-1]) * 4}x" for f, a in zip(layout.split(), attributes))
    vao = ctx.vertex_array(
        program, [(vbo, fmt, *[a for a in attributes if a in program]), (ibo, "4f 4f/i", "in_place", "in_params")]
    )
    FRAME_BLOCK.write(
        ctx,
        u_inv_view_proj=np.identity(4),
        u_camera=np.asarray(eye, float),
        u_time=0.0,
        u_sun_dir=np.zeros(3),
        u_exposure=1.0,
        u_sun_color=np.zeros(3),
        u_sky_ambient=np.zeros(3),
        u_ground_ambient=np.zeros(3),
    )
    set_uniforms(
        program, u_view_proj=np.identity(4), u_relief_depth=depth, u_fin_fade=np.array(fade, float), u_wind=np.zeros(3)
    )
    sampler_units(program)  # each sampler on a unit of its own: samplers of two types may not share one
    out = ctx.buffer(np.full(len(positions) * 6 * 4, np.nan, np.float32).tobytes())
    target = RenderTarget(ctx, (4, 4))  # transform feedback still wants a complete framebuffer bound
    target.use()
    vao.transform(out, moderngl.TRIANGLES, vertices=len(verts))
    target.release()
    data = np.frombuffer(out.read(), np.float32).reshape(-1, 4)
    data = data[~np.isnan(data[:, 0])]
    for obj in (vao, vbo, ibo, out):
        obj.release()
    return data


def trunk_triangles():
    mesh = generate_tree(OAK, 3).lods[1]
    tri = mesh.branch_indices.reshape(-1, 3)
    return mesh.branches[tri, 0:3], mesh.branches[tri, 3:6]


def fade_band(positions, eye):
    """A fade band across the middle of the trunk's distances: some fins full, some narrowed, some gone."""
    d = np.linalg.norm(positions.reshape(-1, 3) - eye, axis=1)
    lo, hi = np.percentile(d, [30, 70])
    return float(lo), float(hi)


@pytest.mark.parametrize("faded", [False, True])
def test_fins_match_the_numpy_reference_on_a_trunk(ctx, programs, faded):
    positions, normals = trunk_triangles()
    eye = np.array([3.0, 2.0, 9.0])
    fade = fade_band(positions, eye) if faded else (1e6, 2e6)
    triangles, quads = extrude_fins(positions, normals, eye, 0.05, fade)
    captured = capture_fins(ctx, programs, positions, normals, eye, 0.05, fade)
    assert len(quads) > 50 if not faded else len(quads) > 20
    if faded:  # the band narrows fins and drops the far ones
        _, unfaded = extrude_fins(positions, normals, eye, 0.05)
        widths = np.linalg.norm(quads[:, 3] - quads[:, 0], axis=1)
        assert len(quads) < len(unfaded) and widths.min() < 0.04 and np.isclose(widths.max(), 0.05, atol=1e-4)
    assert len(captured) == len(quads) * 6  # two triangles per fin, none for the other triangles
    # Strip order V0, V3, V1, V2 as triangles (V0 V3 V1) (V1 V3 V2) -> compare as point sets.
    for k, quad in enumerate(quads):
        fin = captured[6 * k : 6 * k + 6]
        expected = np.array([quad[0], quad[3], quad[1], quad[2]])
        got = np.unique(np.round(fin[:, :3], 4), axis=0)
        assert len(got) == len(np.unique(np.round(expected, 4), axis=0))  # a fin faded to 0 at one end is a triangle
        for k, (point, w) in enumerate(zip(expected, (0, 1, 0, 1))):
            nearest = np.argmin(np.linalg.norm(fin[:, :3] - point, axis=1))
            assert np.linalg.norm(fin[nearest, :3] - point) < 1e-4
            if w == 0 or np.linalg.norm(point - expected[k - 1]) > 1e-4:  # a zero-width end has both w
                assert fin[nearest, 3] == w
        # Silhouette points lie where N.V = 0 (the interpolated normal is perpendicular to the view).
        for point, top in ((quad[0], quad[3]), (quad[1], quad[2])):
            if np.linalg.norm(top - point) < 1e-6:
                continue  # faded to nothing at this end
            n = (top - point) / np.linalg.norm(top - point)
            assert abs(np.dot(n, (eye - point) / np.linalg.norm(eye - point))) < 0.2


def test_no_fin_without_a_sign_change_and_none_for_degenerate(ctx, programs):
    front = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], float)
    normals = np.array([[[0, 0, 1]] * 3], float)
    eye = (0.3, 0.3, 5.0)
    assert len(extrude_fins(front, normals, eye, 0.1)[1]) == 0
    assert len(capture_fins(ctx, programs, front, normals, eye, 0.1)) == 0
    # One vertex exactly orthogonal to the view, the others in front: both crossings collapse to it.
    eye = np.array([0.0, 0.0, 5.0])
    tri = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], float)
    n0 = np.cross(eye - tri[0, 0], [0, 1, 0])
    n0 /= np.linalg.norm(n0)
    normals = np.array([[n0, [0, 0, 1], [0, 0, 1]]], float)
    assert len(extrude_fins(tri, normals, eye, 0.1)[1]) == 0
    assert len(capture_fins(ctx, programs, tri, normals, eye, 0.1)) == 0


def test_alpha_to_coverage_turns_alpha_into_coverage(ctx, programs):
    """A trunk drawn at LOD fade alpha 0.5 covers 2 of 4 samples of every pixel; without A2C the
    fizzle fade keeps whole pixels, about half of them, each opaque."""
    camera = Camera((0, 1.5, 2.5), (0, 1.5, 0), fov_y=40, near=0.1, far=50)
    results, kept = {}, {}
    for a2c in (True, False):
        tree = one_tree(ctx, programs, alpha_to_coverage=a2c, fins=False, relief=False)
        faded = render(ctx, tree, camera, parts=("trunks",), fade=0.5)
        opaque = render(ctx, tree, camera, parts=("trunks",), fade=1.0)
        inside = opaque.sum(axis=2) > 0.05
        ratio = faded[inside].sum(axis=1) / opaque[inside].sum(axis=1)
        results[a2c] = np.median(ratio[ratio > 0.01])
        kept[a2c] = np.mean(ratio > 0.01)
        tree.release()
    assert results[True] == pytest.approx(0.5, abs=0.02)
    assert results[False] == pytest.approx(1.0, abs=0.02)
    assert kept[True] > 0.99 and kept[False] == pytest.approx(0.5, abs=0.1)


def test_alpha_test_edges_are_hard_and_coverage_edges_soft(ctx, programs, output_dir):
    camera = Camera((0, 5.0, 9.0), (0, 5.0, 0), fov_y=50, near=0.1, far=80)
    images = {}
    for a2c, samples in ((False, 4), (False, 0), (True, 4)):
        tree = one_tree(ctx, programs, alpha_to_coverage=a2c, shadows=False)
        images[a2c, samples] = render(ctx, tree, camera, samples=samples, parts=("leaves",))
        tree.release()
    save(images[True, 4], "trees_leaves_a2c", output_dir)
    save(images[False, 4], "trees_leaves_alpha_test", output_dir)
    # Alpha test: multisampling adds nothing inside a card, so the 4x image equals the 1x image.
    hard = np.abs(images[False, 4] - images[False, 0]).max(axis=2) > 1e-3
    soft = np.abs(images[True, 4] - images[False, 0]).max(axis=2) > 1e-3
    assert hard.mean() < 0.002
    assert soft.mean() > 0.01


def test_lod_fade_curves_are_offset():
    """Both LODs are drawn across the band; the near one stays opaque while the far one fades in."""
    d = np.linspace(40, 80, 81)
    near, far = lod_alphas(d, 45.0, 75.0)
    assert near[0] == 1 and far[0] == 0 and near[-1] == 0 and far[-1] == 1
    assert np.all(np.diff(near) <= 0) and np.all(np.diff(far) >= 0)
    both = (near > 0) & (far > 0)
    assert both.any() and np.all(np.maximum(near, far)[both] >= 0.74)  # never both half transparent


def test_trees_vanish_as_they_shrink_below_a_pixel_or_two(ctx, programs):
    """A tree's alphas fade from whole where its height spans TreeSettings.vanish_rows[0] rows of
    the image to nothing at vanish_rows[1]; a tree that spans fewer rows is not drawn at all."""
    assert list(vanish_alphas([10.0, 3.0, 2.25, 1.5, 1.0], 3.0, 1.5)) == [1.0, 1.0, 0.5, 0.0, 0.0]
    tree = one_tree(
        ctx, programs, "oak", shadows=False, fins=False, impostors=False
    )  # impostors: test_trees_impostors.py
    height = tree.models[next(iter(tree.models))].height
    focal = 100.0  # rows per metre at a metre
    written = []
    for rows in (4.0, 2.25, 1.0):
        tree.prepare((0.0, 0.0, height * focal / rows), focal_rows=focal)  # far: the far LOD only
        (buffer, count), *_ = (v for (species, lod), v in tree.instances.items() if lod == 1)
        written.append(np.frombuffer(buffer.read(), np.float32)[5] if count else 0.0)
    tree.release()
    assert np.allclose(written, [1.0, 0.5, 0.0], atol=1e-6)


def test_tree_frustum_test_is_the_box_corner_test(ctx, programs):
    """The tree pass's plane-by-plane frustum test of its cubes keeps exactly the trees that the
    box-corner test (boxes_visible) keeps."""
    trees = tree_instances(
        np.random.default_rng(3).uniform(-300, 300, (4000, 3)) * [1, 0, 1], "oak", np.random.default_rng(0)
    )
    tree = TreePass(ctx, programs, trees)
    camera = Camera((0, 2.0, 0), (40.0, 5.0, 30.0), fov_y=40, near=0.5, far=250)
    view_projection = camera.view_projection(1.5)
    reach = tree.models[0].height * trees["scale"] + tree.sway()
    box = np.asarray(trees["position"], float), reach[:, None]
    expected = boxes_visible(frustum_planes(view_projection), box[0] - box[1], box[0] + box[1])
    kept = tree._visible(view_projection)
    tree.release()
    assert 0 < expected.sum() < len(trees) and np.array_equal(kept, expected)


def test_leaves_shadow_leaves(ctx, programs, output_dir):
    camera = Camera((0, 5.0, 9.0), (0, 5.0, 0), fov_y=50, near=0.1, far=80)
    lit_tree = one_tree(ctx, programs, shadows=False)
    tree = one_tree(ctx, programs)
    shadows = CascadedShadows(ctx, 512, shadow_far=40.0)
    lit = render(ctx, lit_tree, camera, parts=("leaves",))
    shaded = render(ctx, tree, camera, shadows=shadows, parts=("leaves",))
    save(shaded, "trees_leaf_self_shadow", output_dir)
    leaf = lit.sum(axis=2) > 0.02
    darker = (shaded.sum(axis=2) < 0.8 * lit.sum(axis=2)) & leaf
    assert 0.1 < darker.sum() / leaf.sum() < 0.85  # some leaves in the shade of others, not all
    for obj in (lit_tree, tree, shadows):
        obj.release()


@pytest.mark.parametrize("species", ["oak", "fir", "poplar", "pine"])
def test_single_tree_picture(ctx, programs, species, output_dir):
    tree = one_tree(ctx, programs, species)
    height = tree.models[next(iter(tree.models))].height
    camera = Camera((0, height * 0.45, height * 1.3), (0, height * 0.45, 0), fov_y=55, near=0.1, far=200)
    shadows = CascadedShadows(ctx, 512, shadow_far=60.0)
    image = render(ctx, tree, camera, shadows=shadows, background=(0.45, 0.6, 0.8))
    save(image, f"trees_single_{species}", output_dir)
    sky = np.abs(image - np.array([0.45, 0.6, 0.8])).max(axis=2) < 0.01
    assert 0.05 < 1 - sky.mean() < 0.8  # the tree is there and fits the frame
    tree.release()
    shadows.release()


def crown_fill(ids: np.ndarray) -> float:
    """The share of the crown's convex hull, seen from the side, that the tree covers (rows wider
    than three times the trunk's width only, so the bare trunk below does not count)."""
    covered = ids[..., 0] > 0
    rows = np.flatnonzero(covered.any(axis=1))
    widths = np.array([np.ptp(np.flatnonzero(covered[r])) + 1 for r in rows])
    crown = np.zeros_like(covered)
    wide = rows[widths > 3 * np.percentile(widths, 5)]
    crown[wide] = covered[wide]
    ys, xs = np.nonzero(crown)
    hull = shapely.MultiPoint(np.column_stack([xs, ys]).astype(float)).convex_hull
    gy, gx = np.mgrid[0 : crown.shape[0], 0 : crown.shape[1]]
    inside = shapely.contains_xy(hull, gx.ravel(), gy.ravel()).reshape(crown.shape) | crown
    return float(crown.sum() / inside.sum())


def test_every_species_has_a_dense_crown(ctx, programs):
    """A conifer's crown reads as a dense layered cone, not a skeleton of bare boughs: from the side
    its silhouette fills most of its hull, as the broadleaves' do (the fir of one bough level
    filled 0.45; oak 0.91, poplar 0.80, pine 0.85)."""
    fills = {}
    for species in ("oak", "fir", "poplar", "pine"):
        tree = one_tree(ctx, programs, species)
        height = tree.models[next(iter(tree.models))].height
        camera = Camera((0, height * 0.5, height * 1.25), (0, height * 0.5, 0), fov_y=50, near=0.1, far=300)
        fills[species] = crown_fill(render_ids(ctx, tree, camera)[0])
        tree.release()
    print("crown fill from the side:", {k: round(v, 3) for k, v in fills.items()})
    assert min(fills.values()) > 0.6, fills


def test_wind_sways_the_crown_and_not_the_trunk_base(ctx, programs):
    camera = Camera((0, 3.0, 8.0), (0, 3.0, 0), fov_y=60, near=0.1, far=80)
    tree = one_tree(ctx, programs, fins=False, shadows=False)
    calm, gust = (render(ctx, tree, camera, samples=0, time=t) for t in (0.0, 1.7))
    tree.release()
    moved = np.abs(calm - gust).max(axis=2) > 0.02
    rows = SIZE[1]
    assert moved[: rows // 2].mean() > 0.01  # leaves and upper branches move
    assert moved[-rows // 8 :].mean() < 0.002  # the trunk's foot stays put


def test_lod_cross_fade_has_no_pop_along_a_path(ctx, programs, output_dir):
    """A tree passing through the LOD band in 20 steps (the band slid past it, so only the LOD
    changes, not the view): no step between consecutive frames carries more than 40% of the whole
    change from the near to the far LOD. The control, a band narrower than a step (a hard switch),
    puts all of it into one step."""
    tree = one_tree(ctx, programs, "oak", shadows=False, fins=False)
    distance, band, steps = 50.0, 30.0, 20
    camera = Camera((0, 6.0, distance), (0, 6.0, 0), fov_y=16, near=0.5, far=200)

    def path(width: float) -> list[np.ndarray]:
        frames = []
        for k in range(steps + 1):
            start = distance - k / steps * band + (band - width) / 2 * (width < band)
            tree.settings = replace(tree.settings, lod_band=(start, start + width))
            frames.append(render(ctx, tree, camera))
        return frames

    jumps = {}
    for name, width in (("cross-fade", band), ("hard switch", 0.5)):
        frames = path(width)
        total = np.abs(frames[-1] - frames[0]).mean()
        steps_taken = [np.abs(b - a).mean() / total for a, b in zip(frames, frames[1:])]
        jumps[name] = max(steps_taken)
        assert total > 1e-3, "the two LODs must look different"
        if name == "cross-fade":
            save(np.hstack([frames[0], frames[steps // 2], frames[-1]]), "trees_lod_path", output_dir)
    tree.release()
    print("largest step between frames, share of the whole LOD change:", {k: round(v, 3) for k, v in jumps.items()})
    assert jumps["cross-fade"] < 0.4
    assert jumps["hard switch"] > 0.9


def _prepared_everywhere(tree: TreePass, eye, view_projection, focal_rows) -> dict:
    """The instance rows `prepare` must write, by (species, lod), from every tree of the pass (the
    numpy twin of the cells' shortcut): distance, LOD, impostor (lod 2) and vanish alphas, box
    against the frustum, nearest first."""
    trees = tree.trees
    positions = np.asarray(trees["position"], np.float32)
    heights = (np.array([tree.models[int(k)].height for k in trees["species"]]) * trees["scale"]).astype(np.float32)
    distance = np.linalg.norm(positions - np.asarray(eye, float), axis=1)
    alphas = (*lod_alphas(distance, *tree.settings.lod_band), np.zeros(len(trees)))
    if focal_rows is not None:
        rows = heights * focal_rows / np.maximum(distance, 1e-6)
        start, end = tree.settings.impostor_rows
        share = np.clip((1 / rows - 1 / start) / (1 / end - 1 / start), 0, 1)  # 0: mesh, 1: impostor
        mesh, impostor = lod_alphas(share, 0.0, 1.0, overlap=0.0)
        alphas = (alphas[0] * mesh, alphas[1] * mesh, impostor)
        fade = vanish_alphas(rows, *tree.settings.vanish_rows)
        alphas = tuple(alpha * fade for alpha in alphas)
    reach = (heights + np.float32(tree.sway()))[:, None].astype(float)
    shown = ((alphas[0] > 0) | (alphas[1] > 0) | (alphas[2] > 0)) & boxes_visible(
        frustum_planes(view_projection), positions - reach, positions + reach
    )
    order = np.flatnonzero(shown)
    order = order[np.argsort(distance[order], kind="stable")]
    rows = {}
    for species in tree.models:
        for lod in (0, 1, 2):
            keep = order[(trees["species"][order] == species) & (alphas[lod][order] > 0)]
            rows[species, lod] = np.column_stack(
                [positions[keep], trees["yaw"][keep], trees["scale"][keep], alphas[lod][keep], trees["phase"][keep]]
            )
    return rows


@pytest.mark.parametrize("height, focal_rows", [(1.7, 160.0), (1.7, None), (60.0, 400.0)])
def test_trees_prepared_from_their_cells_are_those_of_every_tree(ctx, programs, height, focal_rows):
    """Trees spread over 3 km (three species): the instances `prepare` writes from the cells near
    the view are exactly those every tree tested one by one gives, in the same order, for views
    in every direction (so the pictures are the same: the cells only skip work)."""
    rng = np.random.default_rng(5)
    positions = rng.uniform(-1500, 1500, (6000, 3)) * [1, 0, 1]
    trees = tree_instances(positions, rng.choice(["oak", "fir", "poplar"], len(positions)), rng)
    tree = TreePass(ctx, programs, trees)
    most = {}  # (species, lod) -> the most trees prepared
    try:
        for heading in np.radians([0, 75, 160, 250]):
            eye = (30.0, height, -40.0)
            camera = Camera(eye, (30 + np.sin(heading), height - 0.1, -40 - np.cos(heading)), near=0.5, far=3000)
            view_projection = camera.view_projection(4 / 3)
            tree.prepare(eye, view_projection, focal_rows)
            expected = _prepared_everywhere(tree, eye, view_projection, focal_rows)
            drawn = 0
            for key, rows in expected.items():
                if key[1] == 2:
                    impostor = tree.impostors.get(key[0])
                    buffer, count = (impostor.instances, impostor.count) if impostor else (None, 0)
                else:
                    buffer, count = tree.instances[key]
                if buffer is None:
                    written = np.zeros((0, 7), np.float32)
                else:
                    written = np.frombuffer(buffer.read(), np.float32).reshape(-1, 8)[:count, :7]
                assert np.array_equal(written, rows.astype(np.float32)), (heading, key, count, len(rows))
                drawn += count
            assert 0 < drawn < len(trees) // 2, drawn
            for key, (_, count) in tree.instances.items():
                most[key] = max(most.get(key, 1), count)
        for key, (buffer, _count) in tree.instances.items():  # grown to the most trees drawn, not to every tree
            assert buffer.size <= 2 * most[key] * INSTANCE_BYTES < np.sum(trees["species"] == key[0]) * INSTANCE_BYTES
    finally:
        tree.release()
