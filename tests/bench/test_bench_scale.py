"""Pieces of `cityshade bench scale` that need no minutes of frames: the street camera carried
from Helsinki into its tiled extract, GL buffer accounting, and the ratios made from measured runs
and the GPU-culling pixel check on a small city (the whole benchmark runs in the slow bench test)."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.bench import scale
from cityshade.maps import load_map, map_city, tiled_extract
from cityshade.render import Renderer, RenderSettings, frame_passes
from cityshade.scene import default_city

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def test_the_street_camera_lands_on_the_same_street_of_the_tiled_extract(helsinki_pbf, tmp_path):
    """The extract's first tile is Helsinki where it was: moved by the camera's shift, Helsinki's
    buildings stand on the tile's (to within what the extract changes: it copies closed building
    ways only, and guesses heights from its own data)."""
    extract = tmp_path / "tiled.osm.pbf"
    tiled_extract(helsinki_pbf, extract, 1_000)
    helsinki, tiled = map_city(load_map(helsinki_pbf)), map_city(load_map(extract))
    start = helsinki.camera("street")
    camera = scale._moved_to(start, helsinki, tiled)
    shift = (np.asarray(camera.eye) - start.eye)[[0, 2]]
    assert np.linalg.norm(shift) > 100.0, "the two scenes' origins differ: the camera must move"
    ours = np.array([m.position for m in helsinki.masses]) + shift
    theirs = np.array([m.position for m in tiled.masses])
    nearest = np.linalg.norm(ours[:, None] - theirs[None], axis=2).min(axis=1)
    assert np.median(nearest) < 0.5 and np.mean(nearest < 1e-6) > 0.1, np.percentile(nearest, [10, 50, 90])
    assert np.allclose(np.asarray(camera.target) - camera.eye, np.asarray(start.target) - start.eye)
    assert camera.eye[1] == start.eye[1] and camera.fov_y == start.fov_y


def test_buffer_bytes_count_each_gl_buffer_once(gl_context):
    class Holder:  # stands in for a cityshade object holding buffers
        __module__ = "cityshade.test"

    first, second, third = (gl_context.buffer(reserve=n) for n in (1000, 24, 8))
    holder, inner = Holder(), Holder()
    holder.a, holder.b, holder.inner, inner.again, inner.c = first, first, inner, first, second
    holder.by_key = {(0, 1): (third, 5), (0, 2): [first]}  # as the trees keep theirs, by species and level
    try:
        assert scale._buffer_bytes(holder, None) == 1032
    finally:
        for buffer in (first, second, third):
            buffer.release()


def _run(source, buildings, street, aerial, reference=None, **more):
    frames = {"street": street, "aerial": aerial}
    if reference:
        frames.update({"street_1k": reference[0], "aerial_1k": reference[1]})
    return {
        "source": source,
        "buildings": buildings,
        "load_seconds": 1.0,
        "resident_bytes": 1000 * buildings,
        "gpu_buffer_bytes": 500 * buildings,
        "device": "llvmpipe (LLVM 15.0.7, 256 bits)",
        "frames": frames,
        "culled_pixels_differing": {"street": 0, "aerial": 3} if buildings <= 1_000 else None,
        **more,
    }


def test_ratios_come_from_the_interleaved_frames():
    viewer = {
        "fps": 11.5,
        "scale": 0.25,
        "quality_steps": "quality -1: shadows every 2nd frame",
        "internal_size": [256, 192],
        "frames": 15,
        "frames_counted": 8,
    }
    cache = {"frames": {"cached": [1.0, 2.0], "uncached": [3.0, 3.0]}, "cache": [], "speedup": 2.0}
    runs = [
        _run("generator", 948, [1.0, 1.2], [0.5, 0.7], grammar_cache=cache),
        _run(
            "generator",
            100_349,
            [1.3, 1.5],
            [2.0, 2.4],
            reference=([1.0, 1.0], [0.8, 0.8]),
            viewer=viewer,
            street_profile_ms={"buildings": 400.0, "trees": 120.0, "frame": 520.0},
        ),
        _run("osm", 1_000, [1.0], [1.0]),
    ]
    result = scale._result(runs, 2, True, (1_000,))
    data = result.to_json()
    assert data["ratios"]["street_100k_over_1k"] == pytest.approx(1.4)
    assert data["ratios"]["aerial_100k_over_1k"] == pytest.approx(2.2 / 0.8, abs=1e-3)
    assert data["ratios"]["bytes_per_building"] == 1000  # llvmpipe: the GPU buffers are in the resident bytes
    assert data["ratios"]["viewer_fps_llvmpipe"] == 11.5
    walked = next(t for t in data["tables"] if t["title"].startswith("Viewer walking"))
    assert walked["rows"][0][3] == "quality -1: shadows every 2nd frame"
    assert data["ratios"]["grammar_cache_speedup"] == 2.0 and data["missing"] == {}
    assert data["ratios"]["culled_pixels_differing"] == 3
    culled = next(t for t in data["tables"] if t["title"].startswith("Pixels differing"))
    assert culled["rows"] == [["generator", 0, 3], ["osm", 0, 3]]
    assert data["timing"]["quick"] is True and data["timing"]["frames_per_path"] == 2
    beside = next(t for t in data["tables"] if t["title"].startswith("Beside"))
    assert [row[1] for row in beside["rows"]] == [329, 22_208, 948, 100_349, 1_000, 20_000]
    profile = next(t for t in data["tables"] if t["title"].startswith("Per pass"))
    assert profile["rows"] == [["buildings", 400.0], ["trees", 120.0], ["frame", 520.0]]


def test_street_profile_times_every_pass_of_the_frame(gl_context):
    city = default_city(blocks=3)
    renderer = Renderer((96, 72), RenderSettings(samples=0), ctx=gl_context)
    try:
        renderer.set_city(city)
        profile = scale.street_profile(renderer, city)
    finally:
        renderer.release()
    passes = [p.name for p in frame_passes(renderer.settings)]
    assert sorted(profile) == sorted([*passes, "frame"])
    assert list(profile.values())[:-1] == sorted(list(profile.values())[:-1], reverse=True)
    assert profile["frame"] == pytest.approx(sum(v for k, v in profile.items() if k != "frame"), abs=0.2)


def test_bytes_per_building_add_gpu_buffers_on_a_hardware_gpu():
    run = _run("generator", 100, [1.0], [1.0])
    assert scale._bytes_per_building(run) == 1000
    assert scale._bytes_per_building({**run, "device": "NVIDIA H200"}) == 1500


def test_grammar_cache_frames_time_both_paths_on_the_same_walk():
    measured = scale.grammar_cache_frames(default_city(blocks=3), frames=2, size=(96, 72))
    assert [len(v) for v in measured["frames"].values()] == [2, 2]
    assert measured["cache"][-1]["resident"] > 0  # the cached renderer did use its cache
    expected = np.median(measured["frames"]["uncached"]) / np.median(measured["frames"]["cached"])
    assert measured["speedup"] == pytest.approx(expected, abs=1e-3)


def test_culled_pixels_compare_gpu_culling_with_none_and_restore_the_settings(gl_context):
    """The counts come from renders with culling 'gpu' and 'off' of both views: a view in which GPU
    culling leaves out a visible building would count its pixels (0 expected)."""
    city = default_city(blocks=3)
    renderer = Renderer((96, 72), RenderSettings(samples=0, culling="frustum"), ctx=gl_context)
    try:
        renderer.set_city(city)
        differing = scale.culled_pixels_differing(renderer, city)
        assert renderer.settings.culling == "frustum"
    finally:
        renderer.release()
    assert differing == {"street": 0, "aerial": 0}
