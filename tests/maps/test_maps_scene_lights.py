"""Street lamps: the clustered light grid against its brute-force twin, the GPU's per-pixel lamp
lists (ground id AOV) against the twin pixel by pixel, and lamps lighting the night but not the day."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import Area, Lamp, MapBuilding, MapData, aerial_camera, map_city, to_scene
from cityshade.render import Renderer, RenderSettings
from cityshade.render.testing import CELL, lamps_reaching_cell, light_grid
from cityshade.scene import Camera

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FACE_GROUND = 9
NIGHT, NOON = (-30.0, 0.0), (50.0, 180.0)


def test_light_grid_lists_exactly_the_lamps_within_reach_of_each_cell():
    rng = np.random.default_rng(4)
    lamps = np.c_[
        rng.uniform(-200, 200, 300), np.full(300, 5.7), rng.uniform(-150, 150, 300), rng.uniform(8, 30, 300)
    ].astype(np.float32)
    grid = light_grid(lamps)
    assert grid.starts[-1] == len(grid.indices)
    for cell in range(grid.cells[0] * grid.cells[1]):
        listed = grid.indices[grid.starts[cell] : grid.starts[cell + 1]]
        assert np.array_equal(listed, lamps_reaching_cell(lamps, grid, cell)), cell
    assert 0 < len(grid.indices) / len(lamps) < 40  # each lamp in a handful of cells, not everywhere


def paved_map(building: shapely.Polygon, pavement: shapely.Polygon, lamps: list[Lamp]) -> MapData:
    """One 12 m building on a paved area, with lamps."""
    return MapData(
        Path("lamps.osm"),
        (24.94, 60.17),
        "EPSG:32635",
        buildings=[MapBuilding(0, "way/1", building, height=12.0)],
        areas=[Area("way/2", pavement, "pavement")],
        lamps=lamps,
    )


def lamp_square(with_lamps: bool = True) -> MapData:
    """A 200 m paved square with a grid of lamps and one building in a corner."""
    lamps = [
        Lamp(f"node/{i}", (float(x), float(y)), height=6.0 + (i % 3))
        for i, (x, y) in enumerate((x, y) for x in range(-60, 61, 24) for y in range(-60, 61, 30))
    ]
    return paved_map(shapely.box(80, 80, 95, 95), shapely.box(-100, -100, 100, 100), lamps if with_lamps else [])


@pytest.fixture(scope="module")
def square_city():
    return map_city(lamp_square())


def test_gpu_lamp_lists_match_the_twin_pixel_by_pixel(gl_context, square_city):
    size = (96, 96)
    camera = Camera((0.0, 150.0, 0.0), (0.0, 0.0, 0.0), fov_y=60.0, near=50.0, far=400.0, up=(0.0, 0.0, -1.0))
    renderer = Renderer(size, RenderSettings(samples=0, sun=NIGHT, shadows=False), ctx=gl_context)
    try:
        renderer.set_city(square_city)
        ids = renderer.render_ids(camera)
    finally:
        renderer.release()
    rays = camera.pixel_rays(size)
    ground = camera.eye + rays * (-camera.eye[1] / rays[..., 1:2])  # the y = 0 surface under each pixel
    lamps = square_city.lights
    grid = light_grid(lamps)
    near_post = np.min(np.hypot(ground[..., 0, None] - lamps[:, 0], ground[..., 2, None] - lamps[:, 2]), axis=-1) < 0.6
    offset = (ground[..., [0, 2]] - np.array(grid.origin)) / CELL
    on_border = np.any(np.abs(offset - np.round(offset)) * CELL < 0.02, axis=-1)
    check = (ids[..., 0] == FACE_GROUND) & ~near_post & ~on_border
    assert check.mean() > 0.8
    cells = grid.cell_of(ground[..., 0], ground[..., 2])
    expected = np.vectorize(lambda c: len(lamps_reaching_cell(lamps, grid, c)))(cells)
    differ = int(np.sum(ids[..., 1][check] != expected[check]))
    assert differ == 0, f"{differ} of {int(check.sum())} pixels list a different number of lamps"
    assert len(np.unique(expected[check])) > 3


def render(city, sun, camera, **settings):
    from cityshade.api import render_city

    return render_city(city, camera=camera, size=(96, 64), samples=0, frames=0, sun=sun, shadows=False, **settings)[0]


def test_lamps_light_the_night_near_them_and_not_the_day(square_city):
    dark = map_city(lamp_square(with_lamps=False))
    camera = "square"  # the aerial view frames the building in the corner; this one the square
    over = aerial_camera(to_scene([(-100, -100), (100, -100), (100, 100), (-100, 100)]), 12.0)
    square_city.viewpoints[camera] = dark.viewpoints[camera] = over
    lit_night, dark_night = render(square_city, NIGHT, camera).astype(float), render(dark, NIGHT, camera).astype(float)
    brighter = lit_night.mean(axis=-1) - dark_night.mean(axis=-1)
    assert (brighter > 20).mean() > 0.05  # pools of lamp light on the square
    assert (brighter < -2).mean() < 0.01  # only the posts themselves are darker than the ground they hide
    # by day the lamps are off: only the posts differ
    day_difference = np.abs(render(square_city, NOON, camera).astype(float) - render(dark, NOON, camera)).mean(axis=-1)
    assert (day_difference > 20).mean() < 0.01


def lamp_by_a_wall(with_lamp: bool = True) -> MapData:
    """A building with a lamp a few metres from its west wall."""
    lamps = [Lamp("node/1", (6.0, 13.0), height=6.0)] if with_lamp else []
    return paved_map(shapely.box(10, 10, 25, 25), shapely.box(-40, -10, 40, 40), lamps)


def test_building_lod_leaves_the_lamps_on_near_facades_as_they_are():
    """The LOD colours once shared the lamps' storage binding, so with building LOD on the facades
    read LOD colours as lamps; near the camera, where no facade switches level, on and off agree."""
    lit, dark = map_city(lamp_by_a_wall()), map_city(lamp_by_a_wall(with_lamp=False))
    camera = Camera((-4.0, 3.0, -17.5), (10.0, 4.0, -17.5), fov_y=60.0)
    lit.viewpoints["wall"] = dark.viewpoints["wall"] = camera
    off, on = (render(lit, NIGHT, "wall", building_lod=lod).astype(int) for lod in (False, True))
    lamp_lit = render(dark, NIGHT, "wall").astype(int).sum(axis=-1) + 30 < off.sum(axis=-1)
    assert lamp_lit.mean() > 0.05, "the lamp lights part of the wall"
    differ = int(np.count_nonzero(np.any(on != off, axis=-1)[lamp_lit]))
    assert differ == 0, f"{differ} of {int(lamp_lit.sum())} lamp-lit pixels differ with building LOD on"


def test_lit_roads_get_lamps_on_the_kerb_except_near_mapped_ones():
    from cityshade.maps import Road
    from cityshade.maps.features.lamps import KERB_OFFSET, LIT_ROAD_SPACING, MAPPED_NEARBY, lit_road_lamps

    lit = Road("way/1", shapely.LineString([(0, 0), (350, 0)]), "residential", 8.0, lit=True)
    dark = Road("way/2", shapely.LineString([(0, 50), (350, 50)]), "residential", 8.0)
    mapped = Lamp("node/9", (52.0, -5.0))
    placed = lit_road_lamps(MapData(Path("lit.osm"), (24.94, 60.17), "EPSG:32635", roads=[lit, dark], lamps=[mapped]))
    xy = np.array([lamp.position for lamp in placed])
    assert np.allclose(xy[:, 1], -(4.0 + KERB_OFFSET))  # the right-hand kerb of an eastbound road
    assert np.allclose((xy[:, 0] - LIT_ROAD_SPACING / 2) % LIT_ROAD_SPACING, 0)  # evenly spaced along it
    assert len(placed) == 350 // LIT_ROAD_SPACING - 1  # one gives way to the mapped lamp
    assert np.all(np.hypot(xy[:, 0] - 52.0, xy[:, 1] + 5.0) >= MAPPED_NEARBY)
