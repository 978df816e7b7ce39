"""CityJSON drawn as given: real LoD2 files, every geometry and city object type, LoDs, CityJSONSeq."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from cityshade.errors import CityshadeError
from cityshade.maps import guess_missing, load_map, map_city
from cityshade.maps.features.city_objects import object_material
from cityshade.scene import (
    GROUND_ASPHALT,
    GROUND_BALLAST,
    GROUND_GRASS,
    GROUND_LAND,
    GROUND_PAVEMENT,
    GROUND_PLATFORM,
    GROUND_WATER,
)

DATA = Path(__file__).parents[1] / "data" / "cityjson"
EVERY_TYPE = {
    "Building": 4,
    "BuildingPart": 1,
    "Road": 1,
    "Railway": 1,
    "TransportSquare": 1,
    "Waterway": 1,
    "WaterBody": 1,
    "LandUse": 2,
    "PlantCover": 1,
    "Bridge": 1,
    "Tunnel": 1,
    "CityFurniture": 1,
    "GenericCityObject": 1,
    "SolitaryVegetationObject": 1,
    "TINRelief": 1,
}


def _layer(city, name="city_objects"):
    return next(layer for layer in city.layers if layer.name == name)


def test_zurich_lod2_parts_load_with_heights_as_given():
    data = load_map(DATA / "zurich_lod2.city.json")
    assert data.drawn_types == {"Building": 49, "BuildingPart": 157}  # 4 parts have no area seen from above
    assert data.report.skipped[("building", "zero area (under 0.5 m²)")] == 4
    given = [b for b in data.buildings if b.surfaces is not None]
    assert len(given) == 157 and all(b.is_part and b.parent is not None for b in given)
    grounds = np.array([b.ground for b in given])
    assert 390.0 < grounds.min() == data.ground_level and grounds.max() < 620.0  # metres above sea level
    city = map_city(data)
    heights = np.array([m.height for m in city.masses])
    assert len(city.masses) == 148 and 400.0 < heights.min() and heights.max() < 640.0
    aerial = city.viewpoints["aerial"]
    assert aerial.target[1] == pytest.approx(data.ground_level)  # framed where the model stands
    street = city.viewpoints["street"]
    assert 390.0 < street.position[1] < 640.0


def test_parts_of_one_building_share_its_facade_style():
    data = guess_missing(load_map(DATA / "zurich_lod2.city.json"))
    city = map_city(data)
    by_parent = {}
    for mass in city.masses:
        building = data.buildings[mass.seed]
        by_parent.setdefault(building.parent, set()).add(mass.style)
    assert len(by_parent) > 20 and all(len(styles) == 1 for styles in by_parent.values())


def test_delft_every_city_object_becomes_ground_of_its_class():
    data = load_map(DATA / "delft_subset.city.json")
    assert data.crs == "EPSG:32631"  # EPSG:7415, RD New + NAP: its plan part, heights kept
    assert data.drawn_types == {
        "Building": 24,
        "Road": 8,
        "LandUse": 6,
        "PlantCover": 6,
        "GenericCityObject": 4,
        "Bridge": 2,
        "WaterBody": 2,
    }
    ground = _layer(map_city(data)).ground
    materials = set(np.unique(ground[:, 3]).astype(int).tolist())
    assert {GROUND_ASPHALT, GROUND_GRASS, GROUND_WATER, GROUND_PLATFORM, GROUND_LAND} <= materials
    assert np.all(np.abs(ground[:, 1]) < 30.0)  # NAP heights: Delft is near sea level


def test_every_type_file_draws_every_city_object_type():
    data = load_map(DATA / "every_type.city.json")
    assert data.drawn_types == EVERY_TYPE
    kinds = {o.source_id.split("/")[1]: object_material(o) for o in data.city_objects}
    assert kinds == {
        "road": GROUND_ASPHALT,
        "railway": GROUND_BALLAST,
        "square": GROUND_PAVEMENT,
        "canal": GROUND_WATER,
        "pond": GROUND_WATER,
        "park": GROUND_GRASS,
        "yard": GROUND_PAVEMENT,
        "lawn": GROUND_GRASS,
        "bridge": GROUND_PLATFORM,
        "tunnel": GROUND_PLATFORM,
        "bench": GROUND_PLATFORM,
        "kiosk": GROUND_PLATFORM,
        "oak": GROUND_PLATFORM,
        "relief": GROUND_LAND,
    }
    city = map_city(data)
    layer = _layer(city)
    assert len(layer.trees) == 1 and layer.trees["position"][0, 1] == pytest.approx(100.0)  # the oak's base
    assert np.isin([GROUND_BALLAST, GROUND_WATER, GROUND_LAND], layer.ground[:, 3]).all()


def test_every_geometry_type_is_drawn_and_a_template_instance_is_placed():
    data = load_map(DATA / "every_type.city.json")
    by_id = {b.source_id.split("/")[1]: b for b in data.buildings}
    assert by_id["towers"].height == pytest.approx(30.0)  # the MultiSolid's taller solid
    assert len(by_id["towers"].surfaces["WallSurface"]) == 8
    # the CompositeSolid's 12 faces: its two solids' front walls lie in one plane, as do their back walls
    assert by_id["block"].height == pytest.approx(12.0) and len(by_id["block"].surfaces["unclassified"]) == 10
    assert by_id["shell"].surfaces.keys() == {"GroundSurface", "RoofSurface", "WallSurface"}
    bench = next(o for o in data.city_objects if o.type == "CityFurniture")
    ((_, ring),) = bench.faces
    assert np.allclose(ring[:, 2], 100.45) and np.linalg.norm(ring[1, :2] - ring[0, :2]) == pytest.approx(1.8, abs=0.01)
    oak = next(o for o in data.city_objects if o.type == "SolitaryVegetationObject")
    assert max(ring[:, 2].max() for _, ring in oak.faces) == pytest.approx(104.0)  # the template scaled twice


def test_highest_lod_by_default_and_lod_chooses():
    path = DATA / "multi_lod.city.json"
    assert {b.lod for b in load_map(path).buildings} == {"2.2"}
    assert {b.lod for b in load_map(path, "1").buildings} == {"1.3"}  # the highest 1.x
    assert {b.lod for b in load_map(path, "1.2").buildings} == {"1.2"}
    with pytest.raises(CityshadeError, match="no geometry at LoD 3"):
        load_map(path, "3")
    every = load_map(DATA / "every_type.city.json", "1")
    house = next(b for b in every.buildings if b.source_id == "CityObject/house")
    assert house.lod == "1" and house.height == pytest.approx(8.0)


def test_cityjsonseq_reads_feature_by_feature_like_the_document():
    document = load_map(DATA / "every_type.city.json")
    sequence = load_map(DATA / "every_type.city.jsonl")
    assert sequence.drawn_types == document.drawn_types == EVERY_TYPE
    heights = lambda data: sorted((b.source_id, round(b.height, 3), round(b.ground, 3)) for b in data.buildings)  # noqa: E731
    assert heights(sequence) == heights(document)


def test_attributes_feed_levels_use_and_tags():
    data = load_map(DATA / "every_type.city.json")
    house = next(b for b in data.buildings if b.source_id == "CityObject/house")
    assert house.levels == 2 and "levels" in house.tagged
    assert house.kind == "residential" and house.tags["start_date"] == "1931"
    assert house.tags["roof:type"] == "1030" and house.tags["measured_height"] == "9.0"
    mass = next(m for m in map_city(data).masses if m.seed == house.index)
    assert mass.floor_height == pytest.approx(4.5)  # 9 m of house over its 2 storeys
    assert mass.given and mass.base == pytest.approx(100.0) and mass.height == pytest.approx(109.0)


def test_info_json_reports_city_objects_and_lod(capsys):
    from cityshade.commands import main

    assert main(["info", str(DATA / "every_type.city.json"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["city_objects"] == EVERY_TYPE
    assert info["lod"] == {"2": 4, "2.2": 1}


def test_info_lod_option_picks_the_level_and_refuses_a_bad_one(capsys):
    from cityshade.commands import main

    assert main(["info", str(DATA / "multi_lod.city.json"), "--lod", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["lod"] == {"1.3": 10}
    assert main(["info", str(DATA / "multi_lod.city.json"), "--lod", "seven"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "give a CityJSON LoD such as 1, 2 or 2.2" in err


def test_the_street_view_stands_on_the_ground_clear_of_every_building():
    import shapely

    data = load_map(DATA / "delft_subset.city.json")
    street = map_city(data).viewpoints["street"]
    eye = shapely.Point(street.position[0], -street.position[2])  # scene (x, z) -> map (x, y)
    assert all(b.outline.distance(eye) >= 3.0 for b in data.buildings if b.drawn)
    near = min((b for b in data.buildings if b.surfaces), key=lambda b: b.outline.distance(eye))
    assert street.position[1] == pytest.approx(near.ground + 1.7, abs=1.0)  # eye height over the NAP ground
