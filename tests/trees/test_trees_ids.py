"""Trees in the id AOV: trunks and fins FACE_TRUNK, leaf cards and fronds FACE_FOLIAGE.

A single tree: each part's id coverage against the alpha-tested colour pass of the same part, and
the whole tree's faces against the parts' depths. A city view: the trees change no building pixel
of the id AOV other than those they cover, and the trees the id pass leaves out of view none.
"""

import numpy as np
import pytest
from PIL import Image

from cityshade.interior import FACE_NAMES
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import Camera, make_city
from cityshade.trees import TreePass
from cityshade.trees.testing import TreeCells
from trees_scene import one_tree, render, render_ids

FACE = {name: code for code, name in FACE_NAMES.items()}
TRUNK_PARTS, LEAF_PARTS = ("trunks", "fins"), ("leaves", "fronds")
BACKGROUND = (-1.0, -1.0, -1.0)  # no shaded colour is negative


@pytest.fixture(scope="module")
def programs(gl_context):
    from cityshade.gl import ProgramCache

    return ProgramCache(gl_context)


def colour_coverage(ctx, tree, camera, parts):
    """Pixels the alpha-tested, single-sample colour pass draws for these parts."""
    image = render(ctx, tree, camera, samples=0, parts=parts, background=BACKGROUND)
    return np.abs(image - np.array(BACKGROUND)).max(axis=2) > 1e-3


@pytest.mark.parametrize("species", ["oak", "fir"])
def test_tree_faces_where_trunk_and_leaves_are(gl_context, programs, species, output_dir):
    ctx = gl_context
    tree = one_tree(ctx, programs, species, alpha_to_coverage=False, shadows=False)
    height = tree.models[next(iter(tree.models))].height
    camera = Camera((0, height * 0.4, height * 0.9), (0, height * 0.4, 0), fov_y=60, near=0.1, far=200)
    trunk_ids, trunk_z = render_ids(ctx, tree, camera, TRUNK_PARTS)
    leaf_ids, leaf_z = render_ids(ctx, tree, camera, LEAF_PARTS)
    ids, _ = render_ids(ctx, tree, camera)
    trunk, leaves = colour_coverage(ctx, tree, camera, TRUNK_PARTS), colour_coverage(ctx, tree, camera, LEAF_PARTS)
    tree.release()
    faces = ids[..., 0]
    Image.fromarray(np.select([faces == FACE["trunk"], faces == FACE["foliage"]], [80, 200], 0).astype(np.uint8)).save(
        output_dir / f"trees_ids_{species}.png"
    )
    # each part alone: its face exactly where the alpha-tested colour pass draws it, nothing else
    trunk_differ = int(np.count_nonzero((trunk_ids[..., 0] == FACE["trunk"]) != trunk))
    leaf_differ = int(np.count_nonzero((leaf_ids[..., 0] == FACE["foliage"]) != leaves))
    assert set(np.unique(trunk_ids[..., 0])) <= {FACE["none"], FACE["trunk"]}
    assert set(np.unique(leaf_ids[..., 0])) <= {FACE["none"], FACE["foliage"]}
    # the whole tree: the nearer part's face (leaves drawn after trunks win ties, depth test <=)
    want = np.select([leaves & (leaf_z <= trunk_z), trunk], [FACE["foliage"], FACE["trunk"]], FACE["none"])
    whole_differ = int(np.count_nonzero(faces != want))
    print(
        f"{species}: {trunk.sum()} trunk and {leaves.sum()} leaf pixels alone, {np.sum(faces == FACE['trunk'])} "
        f"trunk and {np.sum(faces == FACE['foliage'])} foliage in the whole tree; differ: trunk {trunk_differ}, "
        f"leaves {leaf_differ}, whole {whole_differ} of {faces.size}"
    )
    assert trunk.sum() > 100 and leaves.sum() > 500 and np.sum(faces == FACE["trunk"]) > 20
    assert trunk_differ == 0 and leaf_differ == 0 and whole_differ == 0
    assert not ids[..., 1:].any()  # no room, building or label on a tree


def test_trees_change_no_building_pixel_they_do_not_cover(gl_context, monkeypatch):
    city = make_city("default", 0)
    camera = city.camera("street")
    got, culled, count = {}, 0, 0
    for trees in (False, True):
        r = Renderer((160, 120), RenderSettings(trees=trees), ctx=gl_context)
        r.set_city(city)
        got[trees] = r.render_ids(camera)
        if trees:  # the id pass draws only the trees in view (or in cells near it): drawing them all changes no pixel
            culled = int(np.count_nonzero(~r.trees._visible(camera.view_projection(160 / 120))))
            count = len(r.trees.trees)
            # neither the ground cells nor the per-tree frustum test leave any tree out
            monkeypatch.setattr(TreeCells, "candidates", lambda self, *args: np.arange(len(self.cell_of)))
            monkeypatch.setattr(TreePass, "_visible", lambda self, vp, trees: np.ones(len(trees), bool))
            everything = r.render_ids(camera)
            assert culled > 0 and np.array_equal(everything, got[True]), culled
        r.release()
    with_trees, without = got[True], got[False]
    on_tree = np.isin(with_trees[..., 0], [FACE["trunk"], FACE["foliage"]])
    changed = np.any(with_trees != without, axis=2)
    print(
        f"street: {np.sum(with_trees[..., 0] == FACE['trunk'])} trunk, "
        f"{np.sum(with_trees[..., 0] == FACE['foliage'])} foliage pixels; {np.count_nonzero(changed & ~on_tree)} "
        f"other pixels changed; {culled} of {count} trees out of view"
    )
    assert np.sum(with_trees[..., 0] == FACE["trunk"]) > 0 and np.sum(with_trees[..., 0] == FACE["foliage"]) > 0
    assert not np.any(changed & ~on_tree)
    assert not with_trees[on_tree][:, 1:].any()


@pytest.mark.parametrize("building_lod", [False, True], ids=["", "building LOD"])
@pytest.mark.parametrize("culling", ["gpu", "off"])
def test_a_city_of_trees_alone_renders(gl_context, culling, building_lod, output_dir):
    """A park without buildings (a city of trees and ground only): the frame and the id AOV are
    drawn, the tree shows where the AOV has its faces, and no pixel is a building's; with building
    LOD too (no grammar building to evaluate)."""
    from cityshade.scene import GROUND_GRASS, City, Layer
    from cityshade.trees import tree_instances

    trees = tree_instances([(0.0, 0.0, 0.0)], "oak", np.random.default_rng(0))
    lawn = (-100.0, -100.0, 100.0, 100.0)
    city = City("park", 0, [], [(*lawn, GROUND_GRASS)], lawn, layers=(Layer("trees", trees=trees),))
    renderer = Renderer(
        (160, 90), RenderSettings(samples=0, culling=culling, building_lod=building_lod), ctx=gl_context
    )
    try:
        renderer.set_city(city)
        camera = Camera((0.0, 4.0, 24.0), (0.0, 5.0, 0.0))
        image = renderer.render(camera)
        ids = renderer.render_ids(camera)
    finally:
        renderer.release()
    Image.fromarray(image).save(output_dir / f"trees_alone_{culling}{'_lod' if building_lod else ''}.png")
    tree = np.isin(ids[..., 0], [FACE["trunk"], FACE["foliage"]])
    assert 100 < np.count_nonzero(tree) < tree.size // 2, np.count_nonzero(tree)
    assert not ids[..., 2].any()  # no building index anywhere
    # the tree's pixels are darker than the sky above the lawn in the same rows
    assert image[tree].mean() < image[:45][~tree[:45]].mean()
