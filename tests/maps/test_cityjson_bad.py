"""Bad CityJSON: each case repaired or skipped and counted, or one line naming the file."""

from __future__ import annotations

import copy
import json

import pytest

from cityshade.errors import CityshadeError
from cityshade.maps import load_map

SEMANTICS = {
    "surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"}, {"type": "WallSurface"}],
    "values": [[0, 1, 2, 2, 2, 2]],
}
BOX = [[[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]], [[3, 0, 4, 7]]]]
B_BOX = [[[[i + 8 for i in ring] for ring in face] for face in shell] for shell in BOX]
DOCUMENT = {
    "type": "CityJSON",
    "version": "2.0",
    "transform": {"scale": [0.01, 0.01, 0.01], "translate": [0.0, 0.0, 0.0]},
    "CityObjects": {
        "a": {
            "type": "Building",
            "geometry": [{"type": "Solid", "lod": "2", "boundaries": BOX, "semantics": SEMANTICS}],
        },
        "b": {
            "type": "Building",
            "geometry": [{"type": "Solid", "lod": "2", "boundaries": B_BOX, "semantics": SEMANTICS}],
        },
    },
    # two 10 x 8 x 6 m boxes 20 m apart, each with its own vertices
    "vertices": [
        [x * 1000 + d, y * 800, z * 600] for d in (0, 2000) for z in (0, 1) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))
    ],
}


def _load(tmp_path, change, name="bad.city.json"):
    document = copy.deepcopy(DOCUMENT)
    change(document)
    path = tmp_path / name
    path.write_text(json.dumps(document))
    return load_map(path)


def _face(document, i, ring, building="a"):
    document["CityObjects"][building]["geometry"][0]["boundaries"][0][i] = [ring]


def _counted(counter, what, why):
    return counter[(what, why)]


def test_missing_transform_reads_vertices_as_coordinates(tmp_path):
    data = _load(tmp_path, lambda d: d.pop("transform"))
    assert _counted(data.report.repaired, "CityJSON", "no 'transform': vertices read as coordinates") == 1
    assert data.buildings[0].height == pytest.approx(600.0)


def test_vertex_index_out_of_range_skips_the_surface(tmp_path):
    data = _load(tmp_path, lambda d: _face(d, 1, [4, 5, 6, 99]))
    assert _counted(data.report.skipped, "surface", "vertex index out of range (the file has 16 vertices)") == 1
    assert len(data.buildings) == 2 and "RoofSurface" not in data.buildings[0].surfaces


@pytest.mark.parametrize("vertex", [["x", 0, 0], [0, 0], None, [float("nan"), 0, 0], [1e308, 1e308, 1e308]])
def test_vertex_not_three_finite_numbers_skips_its_surfaces(tmp_path, vertex):
    def change(document):
        document["vertices"][7] = vertex
        document["transform"]["scale"] = [1e308 if vertex == [1e308] * 3 else 0.01] * 3

    data = _load(tmp_path, change) if vertex != [1e308] * 3 else None
    if data is None:  # every vertex overflows: nothing left, one line
        with pytest.raises(CityshadeError, match="nothing usable in the map"):
            _load(tmp_path, change)
        return
    assert _counted(data.report.skipped, "surface", "vertex not three finite numbers") == 3  # roof and 2 walls of a
    assert len(data.buildings) == 2


@pytest.mark.parametrize("ring", [[0, 1, 0, 1], [0, 1], [], "ring"])
def test_empty_or_degenerate_surfaces_are_skipped(tmp_path, ring):
    data = _load(tmp_path, lambda d: _face(d, 1, ring))
    why = (
        "degenerate (no area in its plane)"
        if ring == [0, 1, 0, 1]
        else "ring is not a list of at least 3 vertex indices"
    )
    assert _counted(data.report.skipped, "surface", why) == 1


def test_inverted_and_non_planar_polygons_are_turned_and_counted(tmp_path):
    def change(document):
        _face(document, 1, [7, 6, 5, 4])  # the roof facing down
        _face(document, 2, [9, 8, 12, 13], "b")  # a wall facing in
        document["vertices"].append([2100, 0, 700])
        _face(document, 5, [11, 8, 16, 15], "b")  # a wall with a corner 1 m off its plane

    data = _load(tmp_path, change)
    repaired = data.report.repaired
    assert _counted(repaired, "surface", "RoofSurface facing the wrong way: turned") == 1
    assert _counted(repaired, "surface", "WallSurface facing the wrong way: turned") == 1
    assert _counted(repaired, "surface", "not planar (a corner over 0.05 m off its plane): drawn in its plane") == 1
    roof = data.buildings[0].surfaces["RoofSurface"][0]
    assert roof[1, 0] - roof[0, 0] > 0  # counter-clockwise seen from above again


def test_semantics_not_matching_the_boundaries_are_dropped(tmp_path):
    def change(document):
        document["CityObjects"]["a"]["geometry"][0]["semantics"]["values"] = [[0, 1, 2]]

    data = _load(tmp_path, change)
    assert _counted(
        data.report.repaired, "geometry", "semantic values do not match the boundaries, read without semantics"
    )
    assert set(data.buildings[0].surfaces) == {"unclassified"} and len(data.buildings) == 2


def test_parents_and_children_naming_missing_objects_are_ignored(tmp_path):
    def change(document):
        document["CityObjects"]["a"]["children"] = ["nobody"]
        document["CityObjects"]["b"]["type"] = "BuildingPart"
        document["CityObjects"]["b"]["parents"] = ["ghost"]

    data = _load(tmp_path, change)
    assert _counted(
        data.report.repaired, "CityObject", "'children' names 'nobody', which the file does not define (ignored)"
    )
    assert _counted(
        data.report.repaired, "CityObject", "'parents' names 'ghost', which the file does not define (ignored)"
    )
    assert data.drawn_types == {"Building": 1, "BuildingPart": 1}


@pytest.mark.parametrize("system", ["EPSG:999999", "urn:ogc:def:crs:OGC::unknown"])
def test_unknown_crs_keeps_metres_and_says_so(tmp_path, system):
    data = _load(tmp_path, lambda d: d.update(metadata={"referenceSystem": system}))
    assert data.crs == "local" and sum(data.report.fallbacks.values()) == 1


def test_unknown_version_is_read_as_2_0_and_counted(tmp_path):
    data = _load(tmp_path, lambda d: d.update(version="3.7"))
    assert _counted(data.report.fallbacks, "CityJSON", "version '3.7' is not 1.0, 1.1 or 2.0 (read as 2.0)") == 1


def test_cityjsonseq_bad_lines_and_a_second_header_are_skipped_by_line(tmp_path):
    header = {k: v for k, v in DOCUMENT.items() if k != "CityObjects"} | {"CityObjects": {}, "vertices": []}
    feature = {"type": "CityJSONFeature", "id": "a", "CityObjects": {"a": DOCUMENT["CityObjects"]["a"]}}
    feature["vertices"] = DOCUMENT["vertices"]
    lines = [header, feature, {**header, "version": "1.1"}, {"type": "Feature"}, feature]
    text = "\n".join(json.dumps(line) for line in lines) + '\n{"type": "CityJSONFeature", \n'
    path = tmp_path / "bad.city.jsonl"
    path.write_text(text)
    data = load_map(path)
    skipped = data.report.skipped
    assert _counted(skipped, "CityJSON", "a second header (version 1.1) inside the sequence, ignored") == 1
    assert _counted(skipped, "CityJSONFeature", "line is not a CityJSONFeature") == 1
    assert data.report.examples[("CityJSONFeature", "line is not a CityJSONFeature")] == "line 4"
    bad_json = [(what, why) for what, why in skipped if what == "CityJSONFeature" and "invalid JSON" in why]
    assert len(bad_json) == 1 and data.report.examples[bad_json[0]] == "line 6"
    assert len(data.buildings) == 2


def test_a_bad_template_instance_skips_the_object(tmp_path):
    def change(document):
        document["CityObjects"]["b"]["geometry"] = [{"type": "GeometryInstance", "template": 3, "boundaries": [0]}]

    data = _load(tmp_path, change)
    assert any(why.startswith("malformed geometry (geometry instance: template 3") for _, why in data.report.skipped)
    assert len(data.buildings) == 1


def test_a_file_with_nothing_drawable_is_one_line(tmp_path):
    def change(document):
        for obj in document["CityObjects"].values():
            obj["geometry"][0]["boundaries"] = [[[[0, 1, 99]]]]

    with pytest.raises(CityshadeError) as info:
        _load(tmp_path, change)
    message = str(info.value)
    assert "\n" not in message and "bad.city.json" in message and "vertex index out of range" in message
