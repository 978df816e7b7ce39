"""The ground of a map: road ribbons and their joins, markings, bridges and tunnels, water and
parks, checked on the triangles themselves; and the trees the map plants."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import Area, MapBuilding, MapData, MapTree, Road, to_scene
from cityshade.maps.features import city_layers
from cityshade.maps.features.land import BASE_DEPTH, LAND_CELL
from cityshade.maps.features.streets import street_surfaces
from cityshade.maps.features.trees import MAX_FOREST_TREES, map_trees, model_size
from cityshade.scene import GROUND_ASPHALT, GROUND_GRASS, GROUND_LAND, GROUND_PAVEMENT, GROUND_WATER

HELSINKI = (24.9384, 60.1699)


def make_map(**records) -> MapData:
    return MapData(Path("hand.osm"), HELSINKI, "EPSG:32635", **records)


def road(x0, y0, x1, y1, kind="residential", width=8.0, **kwargs) -> Road:
    return Road(f"way/{x0}{y0}{x1}{y1}{kind}", shapely.LineString([(x0, y0), (x1, y1)]), kind, width, **kwargs)


def ground_mesh(map_data: MapData) -> np.ndarray:
    """The ground triangles of every feature's layer, as the city draws them."""
    return np.concatenate([layer.ground for layer in city_layers(map_data)])


def faces(mesh: np.ndarray, material: int, y: float | None = 0.0) -> list[shapely.Polygon]:
    """The mesh's triangles of one material (at height y) as map-space polygons (scene z = -north)."""
    tris = mesh.reshape(-1, 3, 4)
    keep = (tris[:, 0, 3] == material) & (True if y is None else np.all(np.isclose(tris[:, :, 1], y), axis=1))
    return [shapely.Polygon(np.c_[t[:, 0], -t[:, 2]]) for t in tris[keep]]


def area(polygons) -> float:
    return float(sum(p.area for p in polygons))


def test_ribbon_has_the_road_width():
    surfaces = street_surfaces(make_map(roads=[road(0, 0, 100, 0, width=8.0, sidewalk="no")]))
    across = surfaces.carriageway.intersection(shapely.LineString([(50, -20), (50, 20)]))
    assert across.length == pytest.approx(8.0, abs=1e-6)


def test_crossing_roads_join_into_one_surface_and_triangles_do_not_overlap():
    map_data = make_map(roads=[road(0, 0, 100, 0, width=8.0), road(50, -50, 50, 50, width=6.0)])
    surfaces = street_surfaces(map_data)
    assert surfaces.carriageway.geom_type == "Polygon"  # one piece: joined at the crossing
    asphalt = faces(ground_mesh(map_data), GROUND_ASPHALT)
    # triangles tile the joined surface exactly: their areas add up to the union's, with no overlap
    assert area(asphalt) == pytest.approx(surfaces.carriageway.area, rel=1e-6)
    assert shapely.union_all(asphalt).area == pytest.approx(area(asphalt), rel=1e-6)


def test_layers_do_not_overlap_so_nothing_can_z_fight():
    park = Area("way/1", shapely.box(-30, -30, 30, 30), "park")
    water = Area("way/2", shapely.box(20, -30, 60, 30), "water")
    data = make_map(roads=[road(-50, 0, 80, 0)], areas=[park, water])
    mesh = ground_mesh(data)
    flat = [p for m in (GROUND_ASPHALT, GROUND_PAVEMENT, GROUND_GRASS, GROUND_WATER) for p in faces(mesh, m)]
    assert shapely.union_all(flat).area == pytest.approx(area(flat), rel=1e-6)
    # the road crosses the park: the park keeps only what the road and its pavements leave
    assert area(faces(mesh, GROUND_GRASS)) < park.polygon.area - 60 * 8
    assert area(faces(mesh, GROUND_WATER)) > 0.7 * water.polygon.area
    land = mesh[np.isclose(mesh[:, 1], -BASE_DEPTH)]  # the land plane under everything
    assert (land[:, 3] == GROUND_LAND).all() and len(land) % 3 == 0
    extent = np.ptp(land[:, [0, 2]], axis=0)
    assert extent.min() > 700_000  # it reaches the horizon
    # under the map the land comes in cells no wider than LAND_CELL: the rasteriser keeps its depth
    # below the map's surfaces only on small triangles
    tris = land[:, [0, 2]].reshape(-1, 3, 2)
    small = tris[np.ptp(tris, axis=1).max(axis=1) <= LAND_CELL + 1e-3]
    x0, y0, x1, y1 = data.bounds()
    (ax, az), (bx, bz) = to_scene(np.array([[x0, y0], [x1, y1]]))
    covered = shapely.union_all([shapely.Polygon(t) for t in small])
    assert covered.buffer(1e-3).contains(shapely.box(min(ax, bx), min(az, bz), max(ax, bx), max(az, bz)))


def test_no_ground_road_inside_a_building_bridges_lifted_tunnels_left_out():
    building = MapBuilding(0, "way/9", shapely.box(40, -20, 60, 20), height=20.0)
    roads = [
        road(0, 0, 100, 0, sidewalk="no"),
        road(0, 50, 100, 50, layer=-1, tunnel=True),
        road(0, 100, 100, 100, layer=2, bridge=True),
    ]
    mesh = ground_mesh(make_map(roads=roads, buildings=[building]))
    ground = faces(mesh, GROUND_ASPHALT)
    assert ground and all(building.outline.intersection(t).area < 1e-6 for t in ground)
    deck = faces(mesh, GROUND_ASPHALT, y=10.0)  # 5 m per layer
    assert area(deck) == pytest.approx(100 * 8.0, rel=1e-6)
    tunnel = shapely.box(0, 46, 100, 54)
    assert all(tunnel.intersection(t).area < 1e-6 for t in faces(mesh, GROUND_ASPHALT, y=None))


def test_lane_markings_centre_and_dividers_stop_at_crossings():
    # crossing ways share a node, as in OpenStreetMap
    avenue = Road("way/1", shapely.LineString([(0, 0), (100, 0), (200, 0)]), "primary", 14.0, lanes=4)
    side = Road("way/2", shapely.LineString([(100, -60), (100, 0), (100, 60)]), "residential", 6.0)
    surfaces = street_surfaces(make_map(roads=[avenue, side]))
    paint = surfaces.markings
    # four lanes, two-way: a solid centre line and a dashed divider on each side at +-3.5 m
    for y, solid in ((0.0, True), (3.5, False), (-3.5, False)):
        stripe = paint.intersection(shapely.LineString([(10, y), (90, y)]).buffer(0.01))
        covered = stripe.area / (80 * 0.02)
        assert (covered > 0.95) if solid else (0.2 < covered < 0.5), (y, covered)
    assert paint.intersection(shapely.Point(100, 0).buffer(6.0)).area == 0  # the crossing has none
    widths = [shapely.minimum_rotated_rectangle(p) for p in shapely.get_parts(paint)]
    assert min(min(np.ptp(np.asarray(r.exterior.coords), axis=0)) for r in widths if r.area > 0.1) < 0.2


def test_map_trees_size_and_species():
    trees = [
        MapTree("node/1", (0.0, 0.0), height=20.0, genus="Picea"),
        MapTree("node/2", (5.0, 0.0), crown_diameter=8.0, genus="Tilia"),
        MapTree("node/3", (10.0, 0.0), leaf_type="needleleaved"),
        MapTree("node/4", (15.0, 0.0), genus="Betula"),
        MapTree("node/5", (20.0, 0.0), genus="Pinus"),
    ]
    records = map_trees(make_map(trees=trees))
    from cityshade.trees import SPECIES_ORDER

    assert [SPECIES_ORDER[s] for s in records["species"]] == ["fir", "oak", "fir", "poplar", "pine"]
    jitter = records["scale"] / np.array([20.0 / model_size("fir", 0)[0], 8.0 / model_size("oak", 0)[1], 1, 1, 1])
    assert np.all((jitter > 0.84) & (jitter < 1.16))  # the instances' own 0.85..1.15 size variation
    assert np.allclose(records["position"], [(0, 0, 0), (5, 0, 0), (10, 0, 0), (15, 0, 0), (20, 0, 0)])


def test_forest_is_filled_deterministically_and_capped():
    wood = Area("way/5", shapely.Polygon([(0, 0), (200, 0), (0, 200)]), "forest")
    first = map_trees(make_map(areas=[wood]))
    assert np.array_equal(first, map_trees(make_map(areas=[wood])))
    xz = first["position"][:, [0, 2]]
    assert len(first) > 100 and wood.polygon.contains(shapely.MultiPoint(np.c_[xz[:, 0], -xz[:, 1]]))
    huge = Area("way/6", shapely.box(0, 0, 5000, 5000), "forest")
    assert len(map_trees(make_map(areas=[huge]))) <= MAX_FOREST_TREES


def test_railways_two_rails_a_gauge_apart_ballast_for_trains_none_in_tunnels():
    from cityshade.maps import Railway
    from cityshade.maps.features.rail import RAIL_WIDTH, tracks

    train = Railway("way/1", shapely.LineString([(0, 0), (100, 0)]), "rail", gauge=1.524)
    tram = Railway("way/2", shapely.LineString([(0, 30), (100, 30)]), "tram", gauge=1.0)
    metro = Railway("way/3", shapely.LineString([(0, 60), (100, 60)]), "subway", tunnel=True)
    ballast, rails = tracks([train, tram, metro])
    across = rails.intersection(shapely.LineString([(50, -5), (50, 65)]))
    ys = sorted(p.centroid.y for p in shapely.get_parts(across))
    assert ys == pytest.approx([-0.762, 0.762, 29.5, 30.5], abs=1e-6)
    assert all(p.length == pytest.approx(RAIL_WIDTH) for p in shapely.get_parts(across))
    assert ballast.contains(shapely.Point(50, 0)) and not ballast.intersects(shapely.Point(50, 30))


def test_the_shaders_get_the_ground_materials_from_python():
    """Ground material ids reach the shaders through the generated constants, not by hand."""
    from cityshade.scene import MAP_GROUND_MATERIALS
    from cityshade.shader_constants import CONSTANTS

    assert len(MAP_GROUND_MATERIALS) == 10 and all(CONSTANTS[k] == v for k, v in MAP_GROUND_MATERIALS.items())
    assert sorted({GROUND_ASPHALT, GROUND_PAVEMENT, GROUND_GRASS, *MAP_GROUND_MATERIALS.values()}) == list(range(13))
