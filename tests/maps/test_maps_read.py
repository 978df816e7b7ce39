"""Reading maps: OpenStreetMap tags and geometry, GeoJSON, CityJSON, projection, the Helsinki extract."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import load_map
from cityshade.maps.testing import colour, direction, length, osm_reader

DATA = Path(__file__).parents[1] / "data" / "maps"


@pytest.fixture(scope="module")
def tagged():
    return load_map(DATA / "tagged.osm")


def _by_id(data, source_id):
    return [b for b in data.buildings if b.source_id == source_id]


def test_every_simple_3d_buildings_tag_is_read_and_marked_tagged(tagged):
    (office,) = _by_id(tagged, "way/100")
    assert (office.kind, office.height, office.levels, office.roof_shape, office.roof_height) == (
        "office",
        21.5,
        6.0,
        "gabled",
        3.0,
    )
    assert (office.roof_direction, office.roof_orientation, office.roof_angle, office.roof_levels) == (
        45.0,
        "across",
        30.0,
        1.0,
    )
    assert office.building_colour == pytest.approx((211 / 255,) * 3)
    assert office.roof_colour == pytest.approx((0xA5 / 255, 0x2A / 255, 0x2A / 255))
    assert (office.building_material, office.roof_material, office.use) == ("brick", "metal", "office")
    assert office.tagged == {
        "height",
        "levels",
        "roof_shape",
        "roof_height",
        "roof_direction",
        "roof_orientation",
        "roof_angle",
        "roof_levels",
        "building_colour",
        "roof_colour",
        "building_material",
        "roof_material",
        "use",
    }
    assert not tagged.report.fallbacks and not tagged.report.skipped


def test_parts_keep_their_attributes_and_their_outline_stays_only_under_the_floating_one(tagged):
    (office,) = _by_id(tagged, "way/100")
    (low,), (high,) = _by_id(tagged, "way/102"), _by_id(tagged, "way/101")
    assert not office.replaced_by_parts and office.remainder.is_empty
    assert [part for _, part in office.beneath_parts] == [high]
    assert low.is_part and high.is_part and low.parent == high.parent == office.index
    assert (high.height, high.min_height, high.min_level) == (30.0, 3.0, 1.0)
    assert (low.levels, low.roof_shape, low.height) == (4.0, "pyramidal", None)


def test_multipolygon_relation_keeps_its_courtyard_and_roof_has_no_walls(tagged):
    (block,) = _by_id(tagged, "relation/200")
    assert len(block.outline.interiors) == 1 and block.kind == "apartments" and block.roof_direction == 135.0
    assert not block.replaced_by_parts
    (canopy,) = _by_id(tagged, "way/400")
    assert not canopy.has_walls and canopy.use == "fuel"
    for building in tagged.buildings:  # exterior counter-clockwise, holes clockwise
        assert building.outline.exterior.is_ccw
        assert all(not ring.is_ccw for ring in building.outline.interiors)


def test_projection_is_utm_about_the_centre_with_true_metres(tagged):
    assert tagged.crs == "EPSG:32635"  # UTM zone 35N for 24.94 E
    lon, lat = tagged.origin
    assert lon == pytest.approx(24.94, abs=0.002) and lat == pytest.approx(60.17, abs=0.001)
    (office,) = _by_id(tagged, "way/100")
    # 0.0004 deg of longitude x 0.0002 deg of latitude at 60.17 N: 22.2 m x 22.3 m (UTM's grid is turned
    # 1.8 degrees from true north here, so compare side lengths, not bounds)
    sides = np.linalg.norm(np.diff(np.asarray(office.outline.exterior.coords), axis=0), axis=1)
    assert sorted(sides) == pytest.approx([22.2, 22.2, 22.3, 22.3], abs=0.1)
    x0, y0, x1, y1 = tagged.bounds()
    assert abs(x0 + x1) < 5.0 and abs(y0 + y1) < 5.0  # the origin is the centre of the data (up to the grid turn)


def test_roads_railways_trees_lamps_and_areas(tagged):
    roads = {r.source_id: r for r in tagged.roads}
    primary, footway, residential = roads["way/300"], roads["way/301"], roads["way/302"]
    assert (
        primary.width,
        primary.lanes,
        primary.lit,
        primary.oneway,
        primary.bridge,
        primary.layer,
        primary.sidewalk,
    ) == (12.0, 4, True, True, True, 1, "both")  # 4 lanes x 3 m
    assert footway.width == 3.5 and residential.width == 6.5  # tagged width; class default
    assert primary.line.length == pytest.approx(111.0, rel=0.01)
    (tram,) = tagged.railways
    assert tram.kind == "tram" and tram.gauge == 1.0
    tree = next(t for t in tagged.trees if t.source_id == "node/51")
    assert (tree.height, tree.crown_diameter, tree.leaf_type, tree.genus, tree.species) == (
        12.0,
        6.0,
        "broadleaved",
        "Tilia",
        "Tilia cordata",
    )
    row = [t for t in tagged.trees if t.source_id.startswith("way/304#")]
    assert len(row) == 8 and all(t.leaf_type == "needleleaved" for t in row)  # 55.5 m every 8 m
    (lamp,) = tagged.lamps
    assert lamp.height == 8.0
    assert sorted(a.kind for a in tagged.areas) == ["park", "water"]


@pytest.mark.parametrize(
    "text, metres",
    [
        ("12", 12.0),
        ("12.5 m", 12.5),
        ("12,5", 12.5),
        ("40 ft", 12.192),
        ("12'6\"", 3.81),
        ("tall", None),
        ("nan", None),
        ("1e308", None),
    ],
)
def test_lengths(text, metres):
    assert length(text) == (pytest.approx(metres) if metres is not None else None)


def test_directions_and_colours():
    assert [direction(v) for v in ("N", "sse", "370", "west", "-")] == [0.0, 157.5, 10.0, None, None]
    assert colour("#fff") == (1.0, 1.0, 1.0) and colour("dark_red") == pytest.approx((139 / 255, 0.0, 0.0))
    assert colour("bricky") is None


def _feature(geometry, **properties):
    return {"type": "Feature", "properties": properties, "geometry": geometry}


def _square(x, y, size=0.0002):
    return [[x, y], [x + size, y], [x + size, y + size], [x, y + size], [x, y]]


def test_geojson_polygons_holes_multipolygons_points_and_skipped_types(tmp_path):
    outer, hole = _square(24.0, 60.0, 0.0006), _square(24.0002, 60.0002)
    features = [
        _feature({"type": "Polygon", "coordinates": [outer, hole]}, height=12),
        _feature(
            {"type": "MultiPolygon", "coordinates": [[_square(24.001, 60.0)], [_square(24.002, 60.0)]]},
            **{"building:levels": "3"},
        ),
        _feature({"type": "Polygon", "coordinates": [_square(24.003, 60.0)]}, natural="water"),
        _feature({"type": "Point", "coordinates": [24.0, 60.001]}, natural="tree", genus="Acer"),
        _feature({"type": "Point", "coordinates": [24.001, 60.001]}, highway="street_lamp"),
        _feature({"type": "LineString", "coordinates": [[24.0, 59.999], [24.003, 59.999]]}, highway="service"),
        _feature({"type": "Point", "coordinates": [24.0, 60.002]}, name="a bench"),
        _feature({"type": "GeometryCollection", "geometries": []}),
        _feature({"type": "MultiPoint", "coordinates": [[24.0, 60.0]]}),
    ]
    path = tmp_path / "city.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    data = load_map(path)
    assert len(data.buildings) == 3 and data.buildings[0].height == 12.0
    assert len(data.buildings[0].outline.interiors) == 1
    assert data.buildings[1].source_id == data.buildings[2].source_id == "feature/1"
    assert [a.kind for a in data.areas] == ["water"] and data.trees[0].genus == "Acer" and len(data.lamps) == 1
    assert data.roads[0].width == 4.0
    skipped = {why for (what, why) in data.report.skipped}
    assert "geometry type 'GeometryCollection' is not read" in skipped
    assert "geometry type 'MultiPoint' is not read" in skipped
    assert "a Point that is no tree, street lamp, entrance or shop" in skipped
    assert sum(data.report.skipped.values()) == 3


def test_geojson_in_metres_keeps_its_units(tmp_path):
    square = [[1000.0, 2000.0], [1030.0, 2000.0], [1030.0, 2020.0], [1000.0, 2020.0], [1000.0, 2000.0]]
    path = tmp_path / "metres.geojson"
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [_feature({"type": "Polygon", "coordinates": [square]}, height=12)],
            }
        )
    )
    data = load_map(path)
    assert data.crs == "local" and data.buildings[0].footprint_area == pytest.approx(600.0)


def test_geojson_legacy_crs_member_is_honoured(tmp_path):
    # ETRS-TM35FIN (EPSG:3067) metres near Helsinki
    square = [
        [385000.0, 6672000.0],
        [385020.0, 6672000.0],
        [385020.0, 6672010.0],
        [385000.0, 6672010.0],
        [385000.0, 6672000.0],
    ]
    path = tmp_path / "tm35.geojson"
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3067"}},
                "features": [_feature({"type": "Polygon", "coordinates": [square]})],
            }
        )
    )
    data = load_map(path)
    assert data.crs == "EPSG:32635" and data.origin[1] == pytest.approx(60.17, abs=0.01)
    assert data.buildings[0].footprint_area == pytest.approx(200.0, rel=0.002)


def _cityjson(tmp_path, lods=("2",), **extra):
    # a 10 x 8 m house (ground z = 2) with walls to z = 8 and a gabled roof to z = 11, plus a 2 m high part
    v = [
        [0, 0, 2],
        [10, 0, 2],
        [10, 8, 2],
        [0, 8, 2],
        [0, 0, 8],
        [10, 0, 8],
        [10, 8, 8],
        [0, 8, 8],
        [0, 4, 11],
        [10, 4, 11],
        [10, 8, 2],
        [14, 8, 2],
        [14, 12, 2],
        [10, 12, 2],
        [10, 8, 4],
        [14, 8, 4],
        [14, 12, 4],
        [10, 12, 4],
    ]
    house = [
        [
            [[0, 3, 2, 1]],
            [[0, 1, 5, 4]],
            [[1, 2, 6, 9, 5]],
            [[2, 3, 7, 6]],
            [[3, 0, 4, 8, 7]],
            [[4, 5, 9, 8]],
            [[6, 7, 8, 9]],
        ]
    ]
    shed = [
        [
            [[10, 13, 12, 11]],
            [[10, 11, 15, 14]],
            [[11, 12, 16, 15]],
            [[12, 13, 17, 16]],
            [[13, 10, 14, 17]],
            [[14, 15, 16, 17]],
        ]
    ]
    semantics = {
        "surfaces": [{"type": "GroundSurface"}, {"type": "WallSurface"}, {"type": "RoofSurface"}],
        "values": [[0, 1, 1, 1, 1, 2, 2]],
    }
    objects = {
        "house": {
            "type": "Building",
            "attributes": {"roof:colour": "red"},
            "children": ["shed"],
            "geometry": [{"type": "Solid", "lod": lod, "boundaries": house, "semantics": semantics} for lod in lods],
        },
        "shed": {
            "type": "BuildingPart",
            "parents": ["house"],
            "geometry": [{"type": "MultiSurface", "lod": "1", "boundaries": shed[0]}],
        },
        "tree": {"type": "SolitaryVegetationObject"},
    }
    document = {
        "type": "CityJSON",
        "version": "2.0",
        "transform": {"scale": [1, 1, 1], "translate": [0, 0, 0]},
        "CityObjects": objects,
        "vertices": v,
        **extra,
    }
    path = tmp_path / "house.city.json"
    path.write_text(json.dumps(document))
    return path


def test_cityjson_heights_from_geometry_and_semantic_surfaces(tmp_path):
    data = load_map(_cityjson(tmp_path))
    house, shed = data.buildings
    assert (house.height, house.min_height, house.roof_height) == (9.0, 0.0, 3.0)
    assert house.footprint_area == pytest.approx(80.0) and house.roof_colour == pytest.approx((1.0, 0.0, 0.0))
    assert len(house.surfaces["RoofSurface"]) == 2 and len(house.surfaces["WallSurface"]) == 4
    assert max(ring[:, 2].max() for ring in house.surfaces["RoofSurface"]) == pytest.approx(11.0)  # as given
    assert house.ground == 2.0 and data.ground_level == 2.0
    assert shed.is_part and shed.parent == house.index and (shed.height, shed.min_height) == (2.0, 0.0)
    assert shed.footprint_area == pytest.approx(16.0) and shed.surfaces["unclassified"]
    assert {"height", "min_height", "roof_height"} <= house.tagged
    assert data.crs == "local"
    assert data.drawn_types == {"Building": 1, "BuildingPart": 1}  # the tree has no geometry to draw


def test_cityjson_reference_system_is_projected(tmp_path):
    path = _cityjson(
        tmp_path,
        transform={"scale": [0.001, 0.001, 0.001], "translate": [85000.0, 446000.0, 0.0]},
        metadata={"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"},
    )
    document = json.loads(path.read_text())
    document["vertices"] = (np.asarray(document["vertices"]) * 1000).astype(int).tolist()
    path.write_text(json.dumps(document))
    data = load_map(path)
    assert data.crs == "EPSG:32631"  # Rotterdam, UTM 31N
    assert data.buildings[0].footprint_area == pytest.approx(80.0, rel=0.002)


def _edited(path: Path, edit) -> Path:
    document = json.loads(path.read_text())
    edit(document["CityObjects"])
    path.write_text(json.dumps(document))
    return path


def test_cityjson_building_with_geometry_only_in_its_parts_is_drawn_by_them(tmp_path):
    def move_into_a_part(objects):  # as in published LoD2 data: Buildings hold no geometry of their own
        house = objects["house"]
        objects["main"] = {"type": "BuildingPart", "parents": ["house"], "geometry": house["geometry"]}
        house.update(geometry=[], children=["main", "shed"])

    data = load_map(_edited(_cityjson(tmp_path), move_into_a_part))
    house, shed, main = data.buildings
    assert house.surfaces is None and house.height == 9.0 and house.tags["building"] == "yes"
    assert main.parent == shed.parent == house.index and len(main.surfaces["RoofSurface"]) == 2


def test_cityjson_part_of_a_parent_without_geometry_or_children_loads(tmp_path):
    def orphan(objects):
        objects["house"].update(geometry=[], children=[])

    data = load_map(_edited(_cityjson(tmp_path), orphan))
    (shed,) = data.buildings
    assert (shed.height, shed.min_height) == (2.0, 0.0)
    assert data.report.skipped[("building", "no geometry and no parts with geometry")] == 1


@pytest.mark.parametrize("code", ["999999", "4326"])  # unknown; lon/lat, but the vertices are RD New metres
def test_cityjson_reference_system_that_cannot_place_it_keeps_metres_and_says_so(tmp_path, code):
    path = _cityjson(
        tmp_path,
        transform={"scale": [1, 1, 1], "translate": [85000.0, 446000.0, 0.0]},
        metadata={"referenceSystem": f"https://www.opengis.net/def/crs/EPSG/0/{code}"},
    )
    data = load_map(path)
    assert data.crs == "local" and len(data.buildings) == 2
    assert data.report.fallbacks == {
        ("crs", "unknown coordinate system, or the data is not on the Earth in it (taken as metres)"): 1
    }


def test_helsinki_extract(helsinki_pbf):
    data = load_map(helsinki_pbf)
    outlines = [b for b in data.buildings if not b.is_part]
    parts = [b for b in data.buildings if b.is_part]
    assert len(outlines) >= 400 and len(parts) >= 100
    assert sum(b.replaced_by_parts for b in outlines) >= 5
    assert {b.roof_shape for b in data.buildings} >= {"gabled", "dome", "flat", "hipped"}
    assert 80.0 < sum(r.line.length for r in data.roads) / 1000.0 < 120.0
    assert len(data.trees) >= 649 and len(data.lamps) == 586
    sea = sum(a.polygon.area for a in data.areas if a.source_id == "coastline")
    assert sea > 50_000.0  # the harbour and Kaisaniemenlahti
    buildings = shapely.union_all([b.outline for b in outlines])
    assert (
        shapely.intersection(
            buildings, shapely.union_all([a.polygon for a in data.areas if a.source_id == "coastline"])
        ).area
        < 0.01 * buildings.area
    )


def test_info_prints_counts_and_reasons(capsys):
    from cityshade.commands import main

    assert main(["info", str(DATA / "tagged.osm")]) == 0
    out = capsys.readouterr().out
    assert "buildings: 3  parts: 2  outlines replaced by parts: 0  cut by parts: 1  roofs without walls: 1" in out
    assert "roof shapes tagged: gabled 1, pyramidal 1" in out
    assert "trees: 9  street lamps: 1" in out and "primary 0.11" in out


def test_info_json_counts_tagged_and_guessed_per_attribute(capsys, tmp_path):
    from cityshade.commands import main

    path = tmp_path / "two.geojson"
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    _feature({"type": "Polygon", "coordinates": [_square(24.0, 60.0)]}, height="tall"),
                    _feature({"type": "Polygon", "coordinates": [_square(24.001, 60.0)]}, height=9, natural="water"),
                    _feature({"type": "Polygon", "coordinates": [_square(24.002, 60.0)]}, **{"building:levels": 4}),
                ],
            }
        )
    )
    assert main(["info", str(path), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["buildings"] == 2 and info["water_m2"] == pytest.approx(11.13 * 22.33, rel=0.01)
    assert info["building_attributes"]["levels"]["tagged"] == 1
    assert info["building_attributes"]["height"] == {"tagged": 0, "guessed": 2}
    assert info["fallbacks"] == [
        {"what": "height", "why": "not a number", "count": 1, "example": "feature/0 height=tall"}
    ]


def test_info_on_a_bad_file_is_one_line_and_exit_2(capsys, tmp_path):
    from cityshade.commands import main

    assert main(["info", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "is a directory" in err


def test_tiled_extract_repeats_every_building_on_a_grid(helsinki_pbf, tmp_path):
    from cityshade.maps import tiled_extract

    info = tiled_extract(helsinki_pbf, tmp_path / "tiled.osm.pbf", buildings=1000)
    assert info["tiles"] == 2 and info["buildings"] >= 1000
    tiled, original = load_map(tmp_path / "tiled.osm.pbf"), load_map(helsinki_pbf)
    # every building way is copied, also those the original draws through their relation instead
    ways = (
        sum(b.source_id.startswith("way/") for b in original.buildings)
        + original.report.skipped[("building", "outer ring of a building relation, which is drawn instead")]
    )
    assert len(tiled.buildings) == 2 * ways
    first, second = tiled.buildings[:ways], tiled.buildings[ways:]
    assert [b.footprint_area for b in first] == pytest.approx([b.footprint_area for b in second], rel=0.01)
    assert min(b.outline.bounds[0] for b in second) > max(b.outline.bounds[2] for b in first)  # side by side


@pytest.mark.parametrize(
    "tags, kind",
    [
        ({"natural": "water"}, "water"),
        ({"waterway": "riverbank"}, "water"),
        ({"leisure": "park"}, "park"),
        ({"landuse": "grass"}, "grass"),
        ({"landuse": "forest"}, "forest"),
        ({"natural": "wood"}, "forest"),
        ({"landuse": "meadow"}, "meadow"),
        ({"landuse": "farmland"}, "farmland"),
        ({"natural": "beach"}, "sand"),
        ({"highway": "pedestrian", "area": "yes"}, "pavement"),
    ],
)
def test_land_use_kinds(tmp_path, tags, kind):
    path = tmp_path / "area.geojson"
    path.write_text(json.dumps(_feature({"type": "Polygon", "coordinates": [_square(24.0, 60.0)]}, **tags)))
    (area,) = load_map(path).areas
    assert area.kind == kind


def test_coastline_makes_the_sea_on_its_right(tmp_path):
    # the coastline runs west to east: land (with the buildings) to the north, sea to the south
    coast = {"type": "LineString", "coordinates": [[24.0, 60.001], [24.004, 60.001]]}
    features = [
        _feature(coast, natural="coastline"),
        _feature({"type": "Polygon", "coordinates": [_square(24.0, 60.002)]}),
        _feature({"type": "Polygon", "coordinates": [_square(24.004, 60.0)]}, leisure="park"),
    ]
    path = tmp_path / "coast.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    data = load_map(path)
    (sea,) = [a for a in data.areas if a.kind == "water"]
    x0, y0, _, _ = data.buildings[0].outline.bounds
    coast_y = y0 - 111.3  # 0.001 degrees of latitude below the building's south-west corner
    assert sea.polygon.contains(shapely.Point(x0, coast_y - 3.0))
    assert not sea.polygon.contains(shapely.Point(x0, coast_y + 3.0))
    assert not sea.polygon.intersects(data.buildings[0].outline)


@pytest.mark.parametrize(
    "tags, use",
    [
        ({"building": "yes", "shop": "bakery"}, "retail"),
        ({"building": "yes", "office": "company"}, "office"),
        ({"building": "yes", "amenity": "school"}, "school"),
        ({"building": "church", "amenity": "place_of_worship"}, "church"),
        ({"building:part": "yes"}, None),
        ({"building": "yes"}, None),
    ],
)
def test_building_use(tags, use):
    from cityshade.maps.testing import use_of

    assert use_of(tags) == use


def test_tunnel_roads_and_unknown_lines(tmp_path):
    features = [
        _feature(
            {"type": "LineString", "coordinates": [[24.0, 60.0], [24.001, 60.0]]},
            highway="secondary",
            tunnel="yes",
            layer="-1",
            width="wide",
        ),
        _feature({"type": "LineString", "coordinates": [[24.0, 60.001], [24.001, 60.001]]}, barrier="fence"),
    ]
    path = tmp_path / "lines.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    data = load_map(path)
    (road,) = data.roads
    assert road.tunnel and road.layer == -1 and road.width == 9.0  # 'wide' is no width: the class's
    assert data.report.fallbacks == {("width", "not a width of 0.5..100 m"): 1}
    assert data.report.examples[("feature", "a line that is no road, railway or tree row")] == "feature/1"


def test_measure_load_runs_the_reader_in_a_fresh_process(tmp_path):
    from cityshade.errors import CityshadeError
    from cityshade.maps import measure_load

    result = measure_load(DATA / "tagged.osm")
    assert result["buildings"] == 5 and result["trees"] == 9 and result["peak_bytes"] > 10 * 2**20
    assert result["bytes_per_building"] == pytest.approx(result["peak_bytes"] / 5)
    with pytest.raises(CityshadeError, match="is a directory"):
        measure_load(tmp_path)


def test_a_building_way_that_is_also_a_relations_outer_ring_is_drawn_once(tmp_path):
    text = (
        (DATA / "tagged.osm")
        .read_text()
        .replace(
            '<way id="110"><nd ref="11"/><nd ref="12"/><nd ref="13"/><nd ref="14"/><nd ref="11"/></way>',
            '<way id="110"><nd ref="11"/><nd ref="12"/><nd ref="13"/><nd ref="14"/><nd ref="11"/>'
            '<tag k="building" v="yes"/></way>',
        )
    )
    path = tmp_path / "twice.osm"
    path.write_text(text)
    data = load_map(path)
    assert not _by_id(data, "way/110") and len(_by_id(data, "relation/200")) == 1
    key = ("building", "outer ring of a building relation, which is drawn instead")
    assert data.report.skipped[key] == 1 and data.report.examples[key] == "way/110"


def test_a_file_too_large_for_memory_keeps_its_node_locations_on_disk(monkeypatch):
    """With no memory to spare for the node location index, it goes to a sparse index in a
    temporary file: the same map is read, and the file is gone afterwards."""
    path = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"
    in_memory = load_map(path)
    chosen = []
    choose = osm_reader._location_index

    def recorded(*args):
        chosen.append(choose(*args))
        return chosen[-1]

    monkeypatch.setattr(osm_reader, "_location_index", recorded)
    monkeypatch.setattr(osm_reader, "INDEX_MEMORY_SHARE", 0.0)
    on_disk = load_map(path)
    assert len(chosen) == 1 and chosen[0].startswith("sparse_file_array,")
    assert not Path(chosen[0].partition(",")[2]).parent.exists(), "the temporary index is removed"
    assert pickle.dumps(on_disk.buildings) == pickle.dumps(in_memory.buildings) and in_memory.buildings
    assert pickle.dumps(on_disk.roads) == pickle.dumps(in_memory.roads)
