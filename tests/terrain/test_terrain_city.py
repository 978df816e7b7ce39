"""A map's city on a DEM: the terrain mesh (levels of detail, skirts), ground draped on it, water
flat, buildings seated (none floats or sinks by more than 0.1 m), cameras above the ground."""

from __future__ import annotations

from collections import Counter
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import Area, city_from_map, guess_missing, load_map, map_city
from cityshade.maps.testing import heights
from cityshade.scene import GROUND_TERRAIN, GROUND_WATER
from cityshade.terrain import Terrain, draped, subdivided, terrain_mesh
from cityshade.terrain.testing import dem_over

MAPS = Path(__file__).parents[1] / "data" / "maps"
SEATED = 0.1  # metres a building's base may differ from the ground under it


def hill(x, y):
    """A hillside climbing north-east with a ridge across it: 20 m to about 45 m over the test maps."""
    return 20.0 + 0.06 * x + 0.05 * y + 12.0 * np.sin(x / 40.0) * np.cos(y / 55.0)


@pytest.fixture(scope="module")
def hill_dem(tmp_path_factory):
    data = load_map(MAPS / "parts.osm")
    path = tmp_path_factory.mktemp("dem") / "hill.tif"
    return dem_over(path, data.crs, data.origin, data.bounds(), hill, samples=240, margin=900)


def _grid(heights, spacing=2.0):
    return Terrain(np.asarray(heights, np.float32), 0.0, (len(heights) - 1) * spacing, spacing)


def _plan_area(triangles: np.ndarray) -> np.ndarray:
    t = triangles.reshape(-1, 3, triangles.shape[-1])
    u, v = t[:, 1, :2] - t[:, 0, :2], t[:, 2, :2] - t[:, 0, :2]
    return (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2


def test_the_mesh_covers_the_grid_once_and_is_finest_over_the_focus():
    rows, cols = np.mgrid[0:161, 0:129]
    terrain = _grid(np.sin(rows / 9.0) * 5 + cols * 0.1)
    west, south, east, north = terrain.bounds()
    mesh = terrain_mesh(terrain, (100.0, 100.0, 140.0, 140.0))
    area = _plan_area(mesh)
    lying = np.abs(area) > 1e-9
    assert (area[lying] > 0).all(), "every cell triangle counter-clockwise seen from above"
    assert np.isclose(area[lying].sum(), (east - west) * (north - south))  # no overlap, no gap
    # the vertices of the triangles over the focus are the grid's samples: the surface height_at describes
    t = mesh.reshape(-1, 3, 3)[lying]
    centres = t.mean(axis=1)
    near = (np.abs(centres[:, 0] - 120) < 20) & (np.abs(centres[:, 1] - 120) < 20)
    side = np.linalg.norm(t[near, 0, :2] - t[near, 2, :2], axis=1)
    assert np.allclose(side, 2.0) and np.allclose(t[near, :, 2], terrain.height_at(t[near, :, 0], t[near, :, 1]))
    far = (centres[:, 0] < 10) & (centres[:, 1] < 10)
    assert np.linalg.norm(t[far, 0, :2] - t[far, 2, :2], axis=1).min() >= 4.0, "coarser a chunk away from the focus"


def test_skirts_close_every_crack_between_levels():
    """Seen from above, every point of the grid is covered; seen from the side, wherever two chunks
    of different levels meet, a skirt of the finer chunk hangs below both edges."""
    rows, cols = np.mgrid[0:97, 0:97]
    terrain = _grid(np.cos(rows / 1.3) * 8 + np.sin(cols / 4.0) * 6)  # rough: levels differ by metres
    mesh = terrain_mesh(terrain, (80.0, 80.0, 100.0, 100.0))
    t = mesh.reshape(-1, 3, 3)
    upright = np.abs(_plan_area(mesh)) <= 1e-9
    skirts = t[upright]
    assert len(skirts), "chunks of different levels meet, so skirts hang there"
    # x = 64 m is the edge between the focus chunk (level 0, y from 64 to 128 m) and its west
    # neighbour (level 1): the neighbour's edge runs straight between every other sample
    edge_x = 64.0
    on_edge = skirts[np.all(np.isclose(skirts[:, :, 0], edge_x), axis=1)]
    ys = np.linspace(65, 127, 40)
    fine = terrain.height_at(np.full_like(ys, edge_x), ys)
    samples = np.arange(64.0, 129.0, 4.0)
    coarse = np.interp(ys, samples, terrain.height_at(np.full_like(samples, edge_x), samples))
    spans = [(on_edge[:, :, 1].min(1) <= y) & (on_edge[:, :, 1].max(1) >= y) for y in ys]
    lowest = np.array([on_edge[span][:, :, 2].min() for span in spans])
    assert (lowest < np.minimum(fine, coarse) - 0.5).all(), "a skirt hangs below both edges, closing the crack"
    assert np.abs(fine - coarse).max() > 0.5, "the two levels' edges do differ: there is a crack to close"


def test_draped_ground_splits_conformingly_to_the_step():
    rng = np.random.default_rng(3)
    square = np.array([(0, 0, 0), (100, 0, 0), (100, 0, -60), (0, 0, 0), (100, 0, -60), (0, 0, -60)], float)
    ground = np.column_stack([square, np.full(6, 7.0)]).astype(np.float32)
    split = subdivided(ground, 4.0).reshape(-1, 3, 4)
    plan = split[:, :, [0, 2]]
    assert (np.linalg.norm(plan - np.roll(plan, -1, axis=1), axis=2) <= 4.0 + 1e-4).all()
    assert np.isclose(np.abs(_plan_area(split[:, :, [0, 2, 1]].reshape(-1, 3))).sum(), 6000.0)
    assert (split[:, :, 3] == 7.0).all()
    # watertight: every inner edge is shared by exactly two triangles (no T-junction)
    corners = [[tuple(p) for p in t] for t in np.round(plan, 3).tolist()]
    edges = Counter(frozenset((t[k], t[(k + 1) % 3])) for t in corners for k in range(3))
    assert set(edges.values()) == {1, 2}
    boundary = sum(np.linalg.norm(np.subtract(*sorted(e))) for e, n in edges.items() if n == 1)
    assert np.isclose(boundary, 320.0), "edges seen once are the square's outline only"
    terrain = _grid(rng.uniform(0, 3, (60, 60)))
    out = draped(ground, terrain)
    assert np.allclose(out[:, 1], terrain.scene_height_at(out[:, 0], out[:, 2]), atol=1e-4)


@pytest.fixture(scope="module")
def hill_city(hill_dem):
    data = load_map(MAPS / "parts.osm", terrain=hill_dem)
    return data, map_city(data)


def test_no_building_floats_or_sinks(hill_city):
    """Each building (its parts too) stands at the lowest ground along its outline: its base is never
    more than SEATED above the ground at any footprint vertex (floating), and never more than SEATED
    below the lowest ground sampled every 0.25 m along its outline (sunk)."""
    data, city = hill_city
    guessed = guess_missing(data)
    by_index = {b.index: b for b in guessed.buildings}
    worst = 0.0
    for mass in city.masses:
        building = by_index[mass.seed]  # map masses carry their building's index as their seed
        root = by_index[building.parent] if building.is_part else building
        seat = float(mass.base) - heights(building)[0]  # the ground under it: min_height counts from there
        outline = shapely.get_coordinates(shapely.segmentize(root.outline.exterior, 0.25))
        lowest = float(data.terrain.height_at(outline[:, 0], outline[:, 1]).min())
        corners = shapely.get_coordinates(root.outline.exterior)
        highest_corner_gap = seat - float(data.terrain.height_at(corners[:, 0], corners[:, 1]).min())
        assert highest_corner_gap <= SEATED, f"{building.source_id} floats by {highest_corner_gap:.3f} m"
        assert seat >= lowest - SEATED, f"{building.source_id} sinks by {lowest - seat:.3f} m"
        worst = max(worst, abs(seat - lowest))
    assert len(city.masses) >= 10 and worst <= SEATED


def test_parts_of_one_building_share_one_base(hill_city):
    data, city = hill_city
    by_index = {b.index: b for b in guess_missing(data).buildings}
    seats: dict[int, set] = {}
    for mass in city.masses:
        building = by_index[mass.seed]
        owner = building.parent if building.is_part else building.index
        seats.setdefault(owner, set()).add(round(float(mass.base) - heights(building)[0], 4))
    assert any(by_index[i].is_part for i in {m.seed for m in city.masses})
    assert all(len(s) == 1 for s in seats.values()), seats


def test_the_ground_lies_on_the_terrain_mesh(hill_city):
    """Streets, land and water draped over the mesh: at every draped vertex, the ground is at least
    as high as the terrain mesh under it (which lies BASE_DEPTH below the surface height_at gives)."""
    data, city = hill_city
    layers = {layer.name: layer for layer in city.layers}
    terrain = layers["terrain"].ground
    assert (terrain[:, 3] == GROUND_TERRAIN).all() and len(terrain)
    for name in ("streets", "land", "water"):
        ground = layers[name].ground
        ours = ground[ground[:, 3] != GROUND_WATER]
        if name == "land":
            continue  # the land plane beyond the terrain grid carries its edge on (features/land.py)
        h = data.terrain.scene_height_at(ours[:, 0], ours[:, 2])
        assert (ours[:, 1] >= h - 1e-3).all(), name


def test_water_is_flat_at_the_lowest_ground_of_its_outline(tmp_path, hill_dem):
    data = load_map(MAPS / "parts.osm", terrain=hill_dem)
    pond = shapely.Polygon([(-10, -40), (30, -40), (30, -20), (-10, -20)])
    data.areas.append(Area("way/9", pond, "water", {"natural": "water"}))
    city = map_city(data)
    water = np.concatenate([layer.ground[layer.ground[:, 3] == GROUND_WATER] for layer in city.layers])
    assert len(water) and np.allclose(water[:, 1], data.terrain.lowest_on(pond), atol=1e-3)


def test_cameras_stand_on_the_terrain(hill_city, hill_dem):
    data, city = hill_city
    flat = map_city(replace(data, terrain=None))
    aerial, flat_aerial = city.viewpoints["aerial"], flat.viewpoints["aerial"]
    assert aerial.eye[1] > flat_aerial.eye[1], "the aerial view rises with the relief it frames"
    if "street" in city.viewpoints:
        eye = city.viewpoints["street"].eye
        assert abs(eye[1] - 1.7 - float(data.terrain.scene_height_at(eye[0], eye[2]))) < 1e-6
    spot = "24.94015,60.17002,1.7,90"
    placed, _, _ = city_from_map(None, spot, city=city)
    eye = placed.viewpoints[spot].eye
    assert abs(eye[1] - 1.7 - float(data.terrain.scene_height_at(eye[0], eye[2]))) < 0.2
