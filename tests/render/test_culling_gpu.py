"""GPU-driven visibility (render/_visibility.py): the pictures with culling on and off are the same
pixel for pixel, the GPU's visible set is its numpy twin's, and the flag really switches it."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.frame import hiz_twin, visible_twin
from cityshade.render import Renderer, RenderSettings, frame_passes
from cityshade.scene import Camera, make_city

SIZE = (160, 96)


def differing_pixels(city, cameras, settings: RenderSettings, gl_context) -> tuple[dict, dict]:
    """Per camera: pixels that differ between culling on and off, and buildings drawn with it on."""
    renderers = {
        on: Renderer(SIZE, settings.with_(culling="gpu" if on else "off"), ctx=gl_context) for on in (True, False)
    }
    differing, drawn = {}, {}
    try:
        for renderer in renderers.values():
            renderer.set_city(city)
        for name, camera in cameras.items():
            culled = renderers[True].render(camera)
            visibility = renderers[True].city.visibility
            drawn[name] = int(visibility.drawn(visibility.camera_draws).sum())
            full = renderers[False].render(camera)
            differing[name] = int(np.count_nonzero(np.any(culled != full, axis=-1)))
    finally:
        for renderer in renderers.values():
            renderer.release()
    return differing, drawn


def district_cameras(city) -> dict[str, Camera]:
    """The district's own views, and one from inside it: the eye among the blocks, looking across."""
    cameras = {name: city.camera(name) for name in ("street", "aerial", "corner")}
    cameras["inside"] = Camera((10.0, 25.0, 30.0), (-120.0, 15.0, -90.0), fov_y=70.0, near=0.5, far=2000.0)
    return cameras


def test_culling_on_and_off_give_the_same_pixels(gl_context):
    city = make_city("default")
    differing, drawn = differing_pixels(city, district_cameras(city), RenderSettings(samples=4), gl_context)
    assert differing == dict.fromkeys(differing, 0), f"pixels differing with GPU culling on: {differing}"
    assert drawn["street"] < len(city.masses) // 2, f"the street view hides most buildings: drew {drawn}"


def test_culling_keeps_the_helsinki_pixels(gl_context, helsinki_pbf):
    from cityshade.maps import city_from_map

    city, street, sky = city_from_map(helsinki_pbf, "street", "2025-06-21", "21:00")
    cameras = {"street": city.camera(street), "aerial": city.camera("aerial")}
    differing, drawn = differing_pixels(city, cameras, RenderSettings(samples=4, **sky), gl_context)
    assert differing == dict.fromkeys(differing, 0), f"pixels differing with GPU culling on: {differing}"
    assert drawn["street"] < len(city.masses), drawn


@pytest.fixture(scope="module")
def single_sample(gl_context):
    city = make_city("default")
    renderer = Renderer(SIZE, RenderSettings(samples=0, trees=False), ctx=gl_context)
    renderer.set_city(city)
    yield city, renderer
    renderer.release()


@pytest.mark.parametrize("view", ["street", "aerial", "corner", "closeup", "inside"])
def test_gpu_visible_sets_equal_the_numpy_twin(single_sample, view):
    city, renderer = single_sample
    camera = district_cameras(city).get(view) or city.camera(view)
    renderer.render(camera)
    visibility = renderer.city.visibility
    boxes, view_projection = visibility.boxes, camera.view_projection(SIZE[0] / SIZE[1])
    pyramid = visibility.read_pyramid()
    expected = {
        "occluders": visible_twin(boxes, view_projection, eye=camera.eye),
        "culled": visible_twin(boxes, view_projection, pyramid=pyramid, viewport=SIZE),
    }
    got = {
        "occluders": visibility.drawn(visibility.occluder_draws),
        "culled": visibility.drawn(visibility.camera_draws),
    }
    for kind in expected:
        differing = np.flatnonzero(expected[kind] != got[kind])
        assert len(differing) == 0, f"{view} {kind}: buildings {differing.tolist()} differ from the twin"
    # the other views (shadow cascades, the id AOV) are culled by their frustum alone
    light = Camera(camera.eye + np.array([60.0, 80.0, 40.0]), camera.target, fov_y=50.0, near=1.0, far=600.0)
    light_view_projection = light.view_projection(1.0)
    got_frustum = visibility.drawn(visibility.frustum(light_view_projection))
    assert np.array_equal(got_frustum, visible_twin(boxes, light_view_projection))
    # the Hi-Z test drops only buildings that the frustum kept
    assert np.all(got["culled"] <= visible_twin(boxes, view_projection))


def test_depth_pyramid_equals_its_twin(single_sample):
    city, renderer = single_sample
    renderer.render(city.camera("street"))
    depth = renderer.depth()[::-1]  # GL's row order: bottom row first
    visibility = renderer.city.visibility
    visibility.build_pyramid(renderer.targets["hdr"].depth, 0)
    got = visibility.read_pyramid()
    # level 0: the depth buffer, up to the rounding of its 24-bit values to float (read-back and
    # shader fetch round differently); above it, the reduction exactly
    step = np.abs(got[0] - depth).max()
    assert step <= 2.0**-23, f"level 0 is {step} away from the depth buffer"
    expected = hiz_twin(got[0])
    assert [level.shape for level in got] == [level.shape for level in expected]
    for level, (a, b) in enumerate(zip(got, expected)):
        assert np.array_equal(a, b), f"level {level}: {np.count_nonzero(a != b)} texels differ"
    assert expected[-1].shape == (1, 1) and expected[-1][0, 0] == got[0].max()


def test_hiz_drops_hidden_buildings_and_the_flag_switches_culling(single_sample):
    city, renderer = single_sample
    camera = city.camera("street")
    renderer.render(camera)
    visibility = renderer.city.visibility
    view_projection = camera.view_projection(SIZE[0] / SIZE[1])
    in_frustum = visible_twin(visibility.boxes, view_projection)
    drawn = visibility.drawn(visibility.camera_draws)
    assert drawn.sum() < in_frustum.sum(), "the street's first row hides buildings inside the frustum"
    names = [p.name for p in frame_passes(RenderSettings())]
    assert names.index("occluders") < names.index("hi-z") < names.index("cull") < names.index("buildings")
    assert not {"occluders", "hi-z", "cull"} & {p.name for p in frame_passes(RenderSettings(culling="frustum"))}


@pytest.mark.parametrize("view", ["street", "corner"])
def test_gpu_tree_instances_kept_equal_the_numpy_twin(gl_context, view):
    city = make_city("default")
    renderer = Renderer(SIZE, RenderSettings(samples=0, shadows=False), ctx=gl_context)
    renderer.set_city(city)
    # the meshes of every tree: the far trees' impostor cards are not culled on the GPU (docs/frame.md)
    renderer.trees.settings = renderer.trees.settings.with_(impostors=False)
    try:
        camera = city.camera(view)
        renderer.render(camera)
        trees, pyramid = renderer.trees, renderer.city.visibility.read_pyramid()
        view_projection = camera.view_projection(SIZE[0] / SIZE[1])
        buckets = [key for key, (_, count) in trees.instances.items() if count]
        kept = {key: trees.kept(*key) for key in buckets}
        for key in buckets:
            expected = visible_twin(trees.instance_boxes(*key), view_projection, pyramid=pyramid, viewport=SIZE)
            assert np.array_equal(kept[key], expected), (
                f"{view} trees {key}: {np.count_nonzero(kept[key] != expected)} differ"
            )
        assert sum(k.sum() for k in kept.values()) < sum(len(k) for k in kept.values()), "some trees are culled"
        # a shadow cascade's trees: its frustum alone
        light = Camera(camera.eye + np.array([60.0, 80.0, 40.0]), camera.target, fov_y=50.0, near=1.0, far=600.0)
        trees.cull(light.view_projection(1.0))
        for key in buckets:
            assert np.array_equal(
                trees.kept(*key), visible_twin(trees.instance_boxes(*key), light.view_projection(1.0))
            )
    finally:
        renderer.release()


def test_culling_keeps_the_polygonised_baseline_pixels(gl_context):
    """The baseline's exteriors have the glass cut out: the rooms behind must hide what the
    occluders' solid depth hid."""
    city = make_city("grid")
    # "row": in front of the first tower of a row, looking along it
    cameras = {"orbit": city.camera("orbit"), "row": Camera((-215.0, 30.0, -188.0), (200.0, 30.0, -188.0), fov_y=60.0)}
    settings = RenderSettings(samples=0, polygonised_interiors=True)
    differing, drawn = differing_pixels(city, cameras, settings, gl_context)
    assert differing == dict.fromkeys(differing, 0), f"pixels differing with GPU culling on: {differing}"
    assert drawn["row"] < len(city.masses) // 2, drawn
