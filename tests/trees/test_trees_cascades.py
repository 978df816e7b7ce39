"""Cascade scheduling (§4.3.2) and cascade fitting."""

import numpy as np
import pytest

from cityshade.scene import Camera
from cityshade.trees import (
    EVERY_FRAME,
    PAPER_RATES,
    cascade_view_projection,
    cascades_due,
    split_distances,
    texture_matrix,
)

ALL = ("buildings", "fronds", "leaves", "trunks")
NO_FRONDS = ("buildings", "leaves", "trunks")
LEAVES = ("buildings", "leaves")


def test_frames_0_to_7_redraw_the_papers_cascades_with_their_casters():
    expected = {
        0: [(0, ALL), (1, NO_FRONDS), (2, LEAVES)],  # maps start empty
        1: [(0, ALL), (1, NO_FRONDS)],
        2: [(0, ALL), (2, LEAVES)],
        3: [(0, ALL), (1, NO_FRONDS)],
        4: [(0, ALL)],
        5: [(0, ALL), (1, NO_FRONDS)],
        6: [(0, ALL), (2, LEAVES)],
        7: [(0, ALL), (1, NO_FRONDS)],
    }
    for frame, due in expected.items():
        assert [(i, tuple(sorted(c))) for i, c in cascades_due(frame)] == due
    counts = np.bincount([i for f in range(1, 9) for i, _ in cascades_due(f)], minlength=3)
    assert counts.tolist() == [8, 4, 2]  # every frame, every 2, every 4
    assert all(len(cascades_due(f, EVERY_FRAME)) == 3 for f in range(8))


def test_each_cascade_covers_its_slice_of_the_view():
    camera = Camera((0, 2, 0), (0, 2, -10), near=0.5, far=500)
    inv = np.linalg.inv(camera.view_projection(16 / 9))
    splits = split_distances(0.5, 150.0)
    assert splits[0] == 0.5 and np.isclose(splits[-1], 150.0) and np.all(np.diff(splits) > 0)
    sun = np.array([0.4, 0.6, 0.3])
    for i in range(3):
        m = texture_matrix(
            cascade_view_projection(inv, 0.5, 500, splits[i], splits[i + 1], sun / np.linalg.norm(sun), 1024, 100.0)
        )
        mid = (splits[i] + splits[i + 1]) / 2
        point = m @ np.array([0.0, 2.0, -mid, 1.0])
        assert np.all((point[:3] > 0) & (point[:3] < 1))


@pytest.mark.slow  # about 6 s on two cores, most of it the city's GPU set-up
def test_the_frame_redraws_each_cascade_at_its_rate(gl_context):
    """Inside the renderer's frames 0-4 (the camera moving; every rate skips a frame): the shadow pass redraws exactly the
    cascades `cascades_due` names, with draw calls for their casters; a cascade not due keeps its
    depth map and light matrix untouched, one redrawn takes the moved camera's matrix."""
    from cityshade.frame import parse_time
    from cityshade.render import Renderer, RenderSettings
    from cityshade.trees import SCENE_TIME, park_scene

    city = park_scene()
    start = city.camera("park")
    renderer = Renderer(
        (64, 48), RenderSettings(samples=0, god_rays=False, time_of_day=parse_time(SCENE_TIME)), ctx=gl_context
    )
    renderer.set_city(city)
    for frame in range(5):
        step = np.array([0.7 * frame, 0.0, 0.0])
        camera = Camera(
            tuple(start.eye + step),
            tuple(np.asarray(start.target) + step),
            fov_y=start.fov_y,
            near=start.near,
            far=start.far,
        )
        shadows = renderer.shadows
        before = None if shadows is None else ([m.read() for m in shadows.maps], [m.copy() for m in shadows.matrices])
        renderer.render(camera)
        shadows = renderer.shadows
        redrawn = [(index, casters) for index, casters, _ in shadows.stats.redrawn]
        due = [(index, tuple(sorted(casters))) for index, casters in cascades_due(frame)]
        assert redrawn == due, f"frame {frame}: redrew {redrawn}, due {due}"
        assert all(calls > 0 for _, _, calls in shadows.stats.redrawn)
        if before is not None:
            for index in range(3):
                kept = np.array_equal(shadows.matrices[index], before[1][index])
                same_map = shadows.maps[index].read() == before[0][index]
                if index in dict(redrawn):
                    assert not kept, f"frame {frame}: cascade {index} redrawn with the old camera's matrix"
                else:
                    assert kept and same_map, f"frame {frame}: cascade {index} changed although not due"
    renderer.release()


def test_new_shadow_maps_are_drawn_whole_at_once(gl_context):
    """A new shadow resolution (the viewer's scale changed) makes new maps: the next frame draws
    every cascade with its casters, whichever are due, so no cascade goes without shadows."""
    from cityshade.frame import parse_time
    from cityshade.render import Renderer, RenderSettings
    from cityshade.trees import SCENE_TIME, park_scene

    city = park_scene()
    settings = RenderSettings(samples=0, god_rays=False, time_of_day=parse_time(SCENE_TIME))
    renderer = Renderer((64, 48), settings, ctx=gl_context)
    renderer.set_city(city)
    for _ in range(2):
        renderer.render(city.camera("park"))
    assert len(renderer.shadows.stats.redrawn) < 3  # frame 1: not every cascade is due
    renderer.set_settings(settings.with_(shadow_resolution=256))
    renderer.render(city.camera("park"))
    shadows = renderer.shadows
    assert shadows.resolution == 256 and shadows.maps[0].size == (256, 256)
    drawn = {index: casters for index, casters, _ in shadows.stats.redrawn}
    assert drawn == {i: tuple(sorted(rate.casters)) for i, rate in enumerate(PAPER_RATES)}


@pytest.mark.parametrize("factor", [2, 4])
def test_slowed_rates_redraw_each_cascade_factor_times_less_often_one_at_a_time(factor):
    from cityshade.trees import slowed_rates

    rates = slowed_rates(PAPER_RATES, factor)
    frames = range(1, 16 * factor + 1)
    counts = np.bincount([i for f in frames for i, _ in cascades_due(f, rates)], minlength=3)
    assert counts.tolist() == [16 // rate.every for rate in PAPER_RATES]
    assert all(len(cascades_due(f, rates)) <= 1 for f in frames), "never two cascades on one frame"
    assert [r.casters for r in rates] == [r.casters for r in PAPER_RATES]
    assert slowed_rates(PAPER_RATES, 1) == PAPER_RATES
