"""A footprint map's City (`maps.map_city` of `maps.load_map`): heights, turned object spaces, roofs of
any outline, clear errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.errors import CityshadeError
from cityshade.maps import load_map, map_city
from cityshade.scene import ROOF_PARTS, SURFACE_ROOF, building_vertices, rotation_y

EXAMPLE = Path(__file__).parents[2] / "examples" / "footprints.geojson"


def test_example_loads_every_polygon_with_its_height():
    city = map_city(load_map(EXAMPLE))
    assert len(city.masses) == 5  # a MultiPolygon gives two buildings
    heights = sorted(round(m.height, 1) for m in city.masses)
    assert heights.count(18.0) == 2 and heights[-1] == 32.0  # height 18 (x2), '32 m'; the rest guessed


def test_object_space_follows_the_footprint_and_world_positions_round_trip():
    city = map_city(load_map(EXAMPLE))
    turned = max(city.masses, key=lambda m: m.height)  # the 32 m building is turned ~10 degrees
    assert abs(np.degrees(turned.yaw)) % 90 > 3
    local = np.asarray(turned.footprint)
    assert np.allclose(local.min(axis=0), 0.0)
    world = local @ rotation_y(turned.yaw)[[0, 2]][:, [0, 2]].T + np.asarray(turned.position)
    # the longest side of the turned footprint runs along local x
    edges = np.diff(np.vstack([local, local[:1]]), axis=0)
    longest = edges[np.argmax(np.linalg.norm(edges, axis=1))]
    assert abs(longest[1]) < 1e-5 * np.linalg.norm(longest)  # float32 corners
    assert shapely.Polygon(world).area == pytest.approx(shapely.Polygon(local).area)


def test_roof_covers_a_non_convex_footprint_exactly():
    city = map_city(load_map(EXAMPLE))
    l_shape = max(city.masses, key=lambda m: len(m.footprint))
    assert not shapely.Polygon(l_shape.footprint).equals(shapely.Polygon(l_shape.footprint).convex_hull)
    vertices = building_vertices(l_shape, 0)
    surface = (vertices["ids"][:, 1] == SURFACE_ROOF) & (vertices["ids"][:, 2] == ROOF_PARTS["ROOF_PART_SURFACE"])
    roof = vertices[surface]["local"][:, [0, 2]].astype(float).reshape(-1, 3, 2)  # not the rooftop units
    u, v = roof[:, 1] - roof[:, 0], roof[:, 2] - roof[:, 0]
    area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum()
    assert area == pytest.approx(shapely.Polygon(l_shape.footprint).area, rel=1e-4)


@pytest.mark.parametrize(
    "text, message",
    [
        ('{"type": "FeatureCollection",\n "features": [}', ":2:15: error: invalid JSON"),
        ('{"type": "FeatureCollection", "features": []}', "nothing usable in the map"),
        (
            '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Point", '
            '"coordinates": [1, 2]}}]}',
            "a Point that is no tree, street lamp, entrance or shop (e.g. feature/0)",
        ),
    ],
)
def test_bad_files_name_the_problem(tmp_path, text, message):
    path = tmp_path / "bad.geojson"
    path.write_text(text)
    with pytest.raises(CityshadeError, match=message.replace("(", r"\(").replace(")", r"\)")) as info:
        map_city(load_map(path))
    assert str(path) in str(info.value)


def test_projected_coordinates_stay_in_metres(tmp_path):
    square = [[1000.0, 2000.0], [1030.0, 2000.0], [1030.0, 2020.0], [1000.0, 2020.0], [1000.0, 2000.0]]
    path = tmp_path / "metres.geojson"
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    {
                        "type": "Feature",
                        "properties": {"height": 12},
                        "geometry": {"type": "Polygon", "coordinates": [square]},
                    }
                ],
            }
        )
    )
    (mass,) = map_city(load_map(path)).masses
    assert np.allclose(sorted(mass.extent[[0, 2]]), [20.0, 30.0]) and mass.height == 12.0


def test_osm_extract_gives_its_closed_building_ways():
    city = map_city(load_map(EXAMPLE.with_suffix(".osm")))
    # The footway is no building; the six tagged levels stand below whatever roof the model guessed.
    six_levels, tagged = sorted(round(m.height - m.roof.height, 1) for m in city.masses)
    assert tagged == 40.0 and 6 * 2.5 <= six_levels <= 6 * 4.0


def test_osm_errors_name_line_and_column(tmp_path):
    path = tmp_path / "bad.osm"
    path.write_text('<osm>\n  <node id="1" lat="1" lon="2">\n</osm>\n')
    path.write_text('<osm version="0.6">\n  <node id="1" lat="1" lon="2">\n</osm>\n')
    with pytest.raises(CityshadeError, match=r"bad.osm:3:3: not a readable OpenStreetMap file \(XML parsing error"):
        map_city(load_map(path))
    shapefile = tmp_path / "city.shp"
    shapefile.write_bytes(b"\x00\x00\x27\x0a")
    with pytest.raises(CityshadeError, match="not a map file this reader knows"):
        map_city(load_map(shapefile))
