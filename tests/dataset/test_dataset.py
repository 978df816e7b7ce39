"""cityshade dataset without Ray: config, view sampling, class mapping, and the labels and depth of
rendered samples against the numpy twins (interior ids, triangle ray cast)."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade import assets
from cityshade.assets import LABELS
from cityshade.dataset import (
    CLASS_COLOURS,
    CLASSES,
    IGNORE,
    SampleRenderer,
    Source,
    Streets,
    View,
    class_image,
    instance_image,
    linear_depth,
    load_source,
    normals_from_depth,
    parse_config,
    sample_view,
)
from cityshade.errors import UsageError
from cityshade.interior import InteriorParams, reference_surfaces
from cityshade.relief import relief_atlas
from cityshade.render.testing import GROUND_MARGIN
from cityshade.scene import batch, intersect, make_city

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

SIZE = (160, 120)
WINDOW = CLASSES.index("window")


# --- config ---------------------------------------------------------------------------------------


def test_defaults_and_overrides():
    config = parse_config({"image": {"width": 64, "height": 48}, "classes": {"ignore": ["lamp"]}})
    assert (config.width, config.height, config.fov) == (64, 48, 66.0)
    assert config.ignore == ("lamp",) and config.vehicle_height == (1.2, 2.5)


@pytest.mark.parametrize(
    "data, words",
    [
        ({"classes": {"ignore": ["cloud"]}}, "classes.ignore = 'cloud': unknown class"),
        ({"image": {"colour": 1}}, "image.colour = 1: unknown key"),
        ({"camera": {}}, "camera"),
        ({"time": {"hours": [18.0, 8.0]}}, "low is above high"),
        ({"time": {"dates": ["2025-13-01", "2025-10-01"]}}, "YYYY-MM-DD"),
        ({"image": {"width": "big"}}, "expected an integer"),
    ],
)
def test_bad_config_is_one_line(data, words):
    with pytest.raises(UsageError, match=None) as info:
        parse_config(data, "my.toml")
    message = str(info.value)
    assert words in message and message.startswith("my.toml: ") and "\n" not in message


# --- views ----------------------------------------------------------------------------------------


def test_views_follow_the_seed_and_index_alone():
    source = load_source(city="default")
    config = parse_config({})
    first = [sample_view(i, 11, config, source.streets, source.has_date) for i in range(40)]
    assert first[7] == sample_view(7, 11, config, source.streets, source.has_date)
    assert first != [sample_view(i, 12, config, source.streets, source.has_date) for i in range(40)]
    kinds = {v.kind for v in first}
    assert kinds == {"pedestrian", "vehicle", "aerial"}
    for view in first:
        lo, hi = config.hours
        assert lo <= view.hours <= hi and view.date is None
        if view.kind == "pedestrian":
            assert view.eye[1] == 1.7
        elif view.kind == "vehicle":
            assert 1.2 <= view.eye[1] <= 2.5
        else:
            assert 60.0 <= view.eye[1] <= 250.0 and -60.0 <= view.pitch <= -30.0


# --- classes and depth, numpy only ----------------------------------------------------------------


def test_class_image_maps_faces_labels_and_materials():
    ids = np.zeros((1, 9, 4), np.uint32)
    ids[0, 0] = (10, 0, 0, 0)  # a tree trunk
    ids[0, 1] = (1, 0, 3, 0)  # bay-texture facade
    ids[0, 2] = (4, 7, 3, 0)  # a room behind glass
    ids[0, 3] = (1, 0, 3, LABELS.index("door"))
    ids[0, 4] = (8, 0, 3, 0)  # roof
    ids[0, 5] = (9, 0, 0, 4)  # ground: lane marking
    ids[0, 6] = (9, 0, 0, 10)  # ground: lamp bulb
    ids[0, 7] = (1, 0, 3, LABELS.index("shop"))
    ids[0, 8] = (11, 0, 0, 0)  # leaves
    got = class_image(ids, ignore=("roof",))
    names = ["tree_trunk", "wall", "window", "door", None, "lane_marking", "lamp", "shop_front", "foliage"]
    assert [CLASSES[c] if c != IGNORE else None for c in got[0]] == names
    assert len(CLASS_COLOURS) == len(CLASSES) and len(set(map(tuple, CLASS_COLOURS))) == len(CLASSES)
    assert instance_image(ids)[0].tolist() == [0, 3, 3, 3, 3, 0, 0, 3, 0]  # trees belong to no building


def test_linear_depth_inverts_the_projection():
    from cityshade.scene import Camera

    camera = Camera((0, 0, 0), (0, 0, -1), near=0.3, far=1_000_000.0)
    z = np.array([0.3, 1.0, 12.5, 250.0, 9000.0])
    clip = camera.projection(1.0) @ np.c_[np.zeros((5, 2)), -z, np.ones(5)].T
    buffer = (clip[2] / clip[3] + 1) / 2
    assert np.allclose(linear_depth(buffer, 0.3, 1_000_000.0), z, rtol=1e-5)
    assert np.isinf(linear_depth(np.array([1.0]), 0.3, 1e6)[0])


def test_normals_of_a_tilted_plane():
    k = np.array([[50.0, 0, 15.5], [0, 50.0, 11.5], [0, 0, 1]])
    u, v = np.meshgrid(np.arange(32.0), np.arange(24.0))
    plane = np.array([0.0, -0.6, -0.8])  # n . p = -4: a floor below and ahead, facing the camera
    rays = np.stack([(u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1], np.ones_like(u)], axis=-1)
    z = (-4.0 / (rays @ plane)).astype(np.float32)
    assert np.allclose(normals_from_depth(z, k), plane, atol=1e-3)


# --- rendered samples against the numpy twins -----------------------------------------------------


def _view_of(camera, index=0) -> View:
    f = camera.forward
    heading = float(np.degrees(np.arctan2(f[0], -f[2])) % 360.0)
    return View(
        index,
        "pedestrian",
        tuple(camera.eye),
        heading,
        float(np.degrees(np.arcsin(f[1]))),
        camera.fov_y,
        0.3,
        None,
        12.0,
    )


@pytest.fixture(scope="module")
def interior_sampler():
    city = make_city("interior")
    from cityshade.scene import Layer
    from cityshade.trees import TREE_DTYPE

    city.layers = (Layer("trees", trees=np.zeros(0, TREE_DTYPE)),)
    source = Source("interior", city, Streets(np.zeros((0, 2, 2)), np.zeros(0)), [None] * len(city.masses))
    sampler = SampleRenderer(source, parse_config({"image": {"width": SIZE[0], "height": SIZE[1]}}))
    yield sampler
    sampler.release()


@pytest.mark.parametrize("name", ["front", *(pytest.param(n, marks=pytest.mark.slow) for n in ("corner", "yawed"))])
def test_window_and_depth_agree_with_numpy_twins(interior_sampler, name, output_dir):
    city = interior_sampler.source.city
    view = _view_of(city.viewpoints[name])
    camera = view.camera()
    arrays = interior_sampler.render(view)
    r = interior_sampler.renderer
    params = InteriorParams(
        lights=r.settings.lights or 0.5,
        time=0.0,
        variants=r.textures.room_variants,
        glass_rect=r.textures.glass_rect,
        sprite_alpha=assets.furniture_sprites()[..., 3] / 255.0,
    )
    x0, z0, x1, z1 = city.bounds
    ref, distance = reference_surfaces(
        city.masses,
        camera,
        SIZE,
        params,
        assets.facade_texture()[0][..., 3] / 255.0,
        (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN),
        window_bay_relief=relief_atlas() if r.settings.relief else None,  # recessed windows, as rendered
    )
    ref_window = np.isin(ref[..., 0], [2, 3, 4, 5, 6, 7])
    window = arrays["class"] == WINDOW
    differ = int(np.count_nonzero(window != ref_window))
    total = SIZE[0] * SIZE[1]
    print(f"{name}: {np.count_nonzero(ref_window)} window pixels, {differ} of {total} differ")
    assert ref_window.sum() > 200, "the view shows too few windows to test"
    assert differ <= 0.001 * total
    # depth: the nearest triangle (or the ground plane) along each pixel ray as camera-space z, and
    # the twin's surface where it traces the window bay's recess (14 cm deep: in grazing views the
    # better part of a metre along the ray)
    vertices, _ = batch(city.masses)
    dirs = camera.pixel_rays(SIZE).reshape(-1, 3)
    t, _, _ = intersect(camera.eye, dirs, vertices["position"].astype(np.float64).reshape(-1, 3, 3))
    with np.errstate(divide="ignore", invalid="ignore"):
        ground = np.where(dirs[:, 1] < 0, -camera.eye[1] / dirs[:, 1], np.inf)
    mesh = np.minimum(t, ground)
    recessed = (distance.ravel() > mesh + 1e-3).reshape(SIZE[1], SIZE[0])
    z = (mesh * (dirs @ camera.forward)).reshape(SIZE[1], SIZE[0])
    twin_z = (np.where(recessed.ravel(), distance.ravel(), mesh) * (dirs @ camera.forward)).reshape(z.shape)
    gpu = r.render_ids(camera)
    drawn = np.isfinite(z) & (z < 500)
    same_surface = np.all(ref[..., [0, 2]] == gpu[..., [0, 2]], axis=-1) & drawn
    # where the twin traces the recess, the depth lies behind the wall, as the twin's does (the traced
    # depth itself against the twin: tests/relief/test_relief_depth.py); elsewhere it is the mesh's
    inside = same_surface & recessed
    behind = arrays["depth"][inside] - z[inside]
    print(
        f"{name}: {inside.sum()} recessed pixels, {np.count_nonzero(behind > 1e-3)} behind the wall on the GPU, "
        f"|GPU - twin| median {np.median(np.abs(arrays['depth'] - twin_z)[inside]) * 100 if inside.any() else 0:.3f} cm"
    )
    assert np.all(behind >= -0.01) and np.all(arrays["depth"][inside] <= twin_z[inside] + 0.5)
    flat = same_surface & ~recessed
    with np.errstate(invalid="ignore"):  # inf - inf on the sky
        error = np.abs(arrays["depth"] - z)
    worst = np.unravel_index(np.argmax(np.where(flat, error, 0)), error.shape)
    print(
        f"{name}: depth error max {error[flat].max() * 100:.3f} cm over {flat.sum()} pixels "
        f"(at {worst}: {z[worst]:.2f} m, ids {gpu[worst]}); 99.9th percentile "
        f"{np.percentile(error[flat], 99.9) * 100:.3f} cm"
    )
    assert same_surface.sum() >= 0.99 * drawn.sum()
    near = flat & (z < 100.0)
    assert near.sum() > 0.5 * flat.sum() and error[near].max() <= 0.01
    # beyond, the 24-bit depth buffer's step (z^2 / (near 2^24): 1.9 cm at 300 m) dominates
    assert np.all(error[flat] <= 0.01 + 1e-4 * z[flat])
    palette = CLASS_COLOURS[np.minimum(arrays["class"], len(CLASSES) - 1)]
    Image.fromarray(np.hstack([arrays["rgb"], palette])).save(output_dir / f"dataset_interior_{name}.png")


def test_grammar_windows_are_window_class(output_dir):
    """On the default city's grammar facades, window pixels of the class image are exactly those
    the grammar label AOV calls window or room (the room seen through the glass)."""
    source = load_source(city="default")
    sampler = SampleRenderer(source, parse_config({"image": {"width": SIZE[0], "height": SIZE[1]}}))
    try:
        view = _view_of(source.city.viewpoints["closeup"])
        arrays = sampler.render(view)
        ids = sampler.renderer.render_ids(view.camera())
    finally:
        sampler.release()
    trees = np.isin(arrays["class"], [CLASSES.index("tree_trunk"), CLASSES.index("foliage")])
    grammar = (ids[..., 3] > 0) & (ids[..., 0] != 9) & ~trees  # trees in front of the facade left out
    labelled_window = grammar & np.isin(ids[..., 3], [LABELS.index("window"), LABELS.index("room")])
    window = (arrays["class"] == WINDOW) & grammar
    assert labelled_window.sum() > 500
    differ = int(np.count_nonzero(window != labelled_window))
    print(f"closeup: {labelled_window.sum()} grammar window pixels, {differ} differ ({trees.sum()} behind trees)")
    assert differ <= 0.001 * SIZE[0] * SIZE[1]


def test_tree_classes_are_where_the_frame_draws_trees():
    """The default city's street trees: trunk and foliage classes come from the id AOV's tree faces;
    where the frame's depth lies in front of the id AOV's (a tree drawn in the picture but not in
    the id AOV) is only the leaves' fringe, which the frame's single-sample alpha to coverage keeps
    and the id AOV's alpha test drops."""
    source = load_source(city="default")
    sampler = SampleRenderer(source, parse_config({"image": {"width": SIZE[0], "height": SIZE[1]}}))
    try:
        view = _view_of(source.city.viewpoints["closeup"])
        camera = view.camera()
        arrays = sampler.render(view)
        aov_z = linear_depth(sampler.renderer.depth(aov=True), camera.near, camera.far)
    finally:
        sampler.release()
    classes = arrays["class"]
    trunk, foliage = classes == CLASSES.index("tree_trunk"), classes == CLASSES.index("foliage")
    in_front = arrays["depth"] < aov_z - (0.01 + 1e-3 * np.where(np.isfinite(aov_z), aov_z, 0.0))
    missed = int(np.count_nonzero(in_front & ~trunk & ~foliage))
    print(
        f"closeup: {trunk.sum()} trunk, {foliage.sum()} foliage pixels; {missed} of {classes.size} drawn in "
        f"front of the id AOV but not a tree class"
    )
    assert trunk.sum() > 50 and foliage.sum() > 500
    assert not arrays["instance"][trunk | foliage].any()
    assert missed <= 0.01 * classes.size


def test_intrinsics_and_extrinsics_project_as_the_renderer_does():
    from cityshade.dataset import extrinsics, intrinsics

    view = View(0, "vehicle", (12.0, 2.0, -40.0), 237.0, 4.0, 60.0, 0.3, None, 12.0)
    width, height = 64, 48
    camera = view.camera()
    side = np.cross(camera.forward, [0.0, 1.0, 0.0])
    points = (
        camera.eye
        + np.outer([20.0, 30.0, 9.0], camera.forward)
        + np.outer([3.0, -8.0, 0.5], side)
        + np.outer([1.0, -1.5, 0.2], [0.0, 1.0, 0.0])
    )
    clip = np.c_[points, np.ones(3)] @ camera.view_projection(width / height).T
    ndc = clip[:, :2] / clip[:, 3:4]
    expected = np.c_[(ndc[:, 0] + 1) / 2 * width - 0.5, (1 - ndc[:, 1]) / 2 * height - 0.5]  # pixel centres at integers
    cam = (extrinsics(view) @ np.c_[points, np.ones(3)].T)[:3]
    assert np.all(cam[2] > 0)  # OpenCV: in front of the camera is +z
    pixels = intrinsics(view.fov, width, height) @ cam
    assert np.allclose((pixels[:2] / pixels[2]).T, expected, atol=1e-6)
