"""Bad map input: every case is repaired, skipped or refused with one line naming the file and element."""

from __future__ import annotations

import gzip
import json
import os
from pathlib import Path

import numpy as np
import pytest

from cityshade.errors import CityshadeError
from cityshade.maps import load_map

SQUARE = [(60.0, 24.0), (60.0, 24.0004), (60.0002, 24.0004), (60.0002, 24.0)]
TREE = '<node id="900" lat="60.001" lon="24.001"><tag k="natural" v="tree"/></node>'


def _osm(tmp_path, nodes, ways="", name="map.osm", prolog='<?xml version="1.0" encoding="UTF-8"?>\n') -> Path:
    """An .osm file with nodes (id, lat, lon strings) and raw way/relation XML."""
    body = "\n".join(f'<node id="{i}" lat="{lat}" lon="{lon}"/>' for i, lat, lon in nodes)
    path = tmp_path / name
    path.write_text(f'{prolog}<osm version="0.6">\n{body}\n{ways}\n</osm>\n')
    return path


def _way(way_id, refs, **tags):
    tags = tags or {"building": "yes"}
    return (
        f'<way id="{way_id}">'
        + "".join(f'<nd ref="{r}"/>' for r in refs)
        + "".join(f'<tag k="{k.replace("__", ":")}" v="{v}"/>' for k, v in tags.items())
        + "</way>"
    )


def _square_nodes(first=1, corners=SQUARE):
    return [(first + i, lat, lon) for i, (lat, lon) in enumerate(corners)]


def _refused(path, *needles):
    with pytest.raises(CityshadeError) as info:
        load_map(path)
    message = str(info.value)
    assert info.value.exit_code == 2 and "\n" not in message and str(path) in message
    for needle in needles:
        assert needle in message, message
    return message


@pytest.mark.parametrize(
    "lat, lon", [("nan", "24.0004"), ("inf", "24.0004"), ("1e308", "24.0004"), ("abc", "24.0004"), ("60.0", "-inf")]
)
def test_unreadable_coordinates_name_the_line_and_node(tmp_path, lat, lon):
    nodes = _square_nodes()
    nodes[1] = (2, lat, lon)
    path = _osm(tmp_path, nodes, _way(10, [1, 2, 3, 4, 1]))
    _refused(path, f"{path}:4: node/2", "coordinate")


def test_latitude_out_of_range_skips_the_building_and_says_why(tmp_path):
    nodes = _square_nodes()
    nodes[1] = (2, "95.0", "24.0004")
    path = _osm(tmp_path, nodes, _way(10, [1, 2, 3, 4, 1]))
    _refused(path, "nothing usable", "way/10", "missing node or a bad location")


def test_node_without_latitude_skips_its_building(tmp_path):
    path = tmp_path / "nolat.osm"
    path.write_text(
        '<?xml version="1.0"?>\n<osm version="0.6">\n'
        + "".join(
            f'<node id="{i}" lon="{lon}"' + ("" if i == 2 else f' lat="{lat}"') + "/>"
            for i, lat, lon in _square_nodes()
        )
        + TREE
        + _way(10, [1, 2, 3, 4, 1])
        + "</osm>"
    )
    data = load_map(path)
    assert not data.buildings and len(data.trees) == 1
    assert data.report.examples[("building", "refers to a missing node or a bad location")] == "way/10"


def test_a_file_that_is_not_osm_is_refused(tmp_path):
    path = tmp_path / "junk.osm.pbf"
    path.write_bytes(bytes(range(256)) * 8)
    _refused(path, "not a readable OpenStreetMap file")


def test_missing_node_and_unclosed_way_are_counted_and_the_rest_loads(tmp_path):
    nodes = _square_nodes() + _square_nodes(
        11, [(60.001, 24.0), (60.001, 24.0004), (60.0012, 24.0004), (60.0012, 24.0)]
    )
    ways = _way(10, [1, 2, 3, 77, 1]) + _way(20, [11, 12, 13, 14]) + _way(30, [11, 12, 13, 14, 11])
    data = load_map(_osm(tmp_path, nodes, ways))
    assert [b.source_id for b in data.buildings] == ["way/30"]
    assert data.report.skipped[("building", "refers to a missing node or a bad location")] == 1
    assert data.report.examples[("building", "refers to a missing node or a bad location")] == "way/10"
    assert data.report.examples[("building", "way is not closed")] == "way/20"


def test_duplicate_node_ids_use_the_last_and_are_counted(tmp_path):
    nodes = _square_nodes() + [(2, "60.0", "24.0008")]
    nodes.sort(key=lambda n: n[0])
    data = load_map(_osm(tmp_path, nodes, _way(10, [1, 2, 3, 4, 1])))
    assert data.report.repaired[("node", "duplicate or unsorted node id (the last one is used)")] == 1
    assert data.report.examples[("node", "duplicate or unsorted node id (the last one is used)")] == "node/2"
    assert len(data.buildings) == 1


@pytest.mark.parametrize(
    "corners, parts",
    [
        ([(60.0, 24.0), (60.0002, 24.0004), (60.0, 24.0004), (60.0002, 24.0)], 2),  # a bow tie
        ([(60.0, 24.0), (60.0, 24.0004), (60.0002, 24.0004), (60.0, 24.0002), (60.0002, 24.0)], 2),  # touches itself
    ],
)
def test_self_intersecting_outlines_are_made_valid_keeping_each_polygon(tmp_path, corners, parts):
    nodes = _square_nodes(1, corners)
    refs = list(range(1, len(corners) + 1)) + [1]
    data = load_map(_osm(tmp_path, nodes, _way(10, refs)))
    assert len(data.buildings) == parts and all(b.outline.is_valid for b in data.buildings)
    ((what, why),) = data.report.repaired
    assert what == "building" and why.startswith("invalid outline") and data.report.examples[(what, why)] == "way/10"


def test_zero_area_outline_is_skipped_and_nothing_usable_exits_2(tmp_path):
    nodes = _square_nodes(1, [(60.0, 24.0), (60.0, 24.0002), (60.0, 24.0004), (60.0, 24.0001)])
    path = _osm(tmp_path, nodes, _way(10, [1, 2, 3, 4, 1]))
    _refused(path, "zero area", "way/10")
    data = load_map(_osm(tmp_path, nodes, TREE + _way(10, [1, 2, 3, 4, 1]), "tree.osm"))
    assert data.report.skipped[("building", "zero area (under 0.5 m²)")] == 1 and not data.buildings


@pytest.mark.parametrize(
    "key, value, why",
    [
        ("height", "tall", "not a number"),
        ("height", "-5", "out of range 0..1000"),
        ("height", "0", "out of range 0..1000"),
        ("height", "1e308", "not a number"),
        ("height", "5000", "out of range 0..1000"),
        ("building__levels", "10000", "out of range 0..200"),
        ("roof__angle", "120", "out of range 0..90"),
        ("roof__shape", "banana", "unknown value"),
        ("roof__colour", "bricky", "unknown value"),
        ("roof__direction", "up", "unknown value"),
    ],
)
def test_unreadable_and_absurd_tag_values_fall_back_and_are_counted(tmp_path, key, value, why):
    data = load_map(_osm(tmp_path, _square_nodes(), _way(10, [1, 2, 3, 4, 1], building="yes", **{key: value})))
    (building,) = data.buildings
    osm_key = key.replace("__", ":")
    assert data.report.fallbacks == {(osm_key, why): 1}
    assert data.report.examples[(osm_key, why)] == f"way/10 {osm_key}={value}"
    assert building.tagged == set()


@pytest.mark.parametrize(
    "doctype",
    [
        '<!DOCTYPE osm [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
        '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>\n',
        '<!DOCTYPE osm [<!ENTITY x SYSTEM "file:///etc/hostname">]>\n',
    ],
)
def test_entity_bombs_and_external_entities_are_refused_unexpanded(tmp_path, doctype):
    path = tmp_path / "entities.osm"
    path.write_text(
        f'<?xml version="1.0"?>\n{doctype}<osm version="0.6"><node id="1" lat="60" lon="24">'
        '<tag k="natural" v="tree"/><tag k="genus" v="&x;&c;"/></node></osm>'
    )
    message = _refused(path, "declares a document type or entities")
    hostname = Path("/etc/hostname")
    if hostname.is_file() and hostname.read_text().strip():
        assert hostname.read_text().strip() not in message.split("refusing")[0].replace(str(path), "")


def test_empty_file_directory_missing_file_and_non_regular_file(tmp_path):
    empty = tmp_path / "empty.osm"
    empty.write_bytes(b"")
    _refused(empty, "the file is empty")
    _refused(tmp_path, "is a directory")
    _refused(tmp_path / "absent.osm.pbf", "cannot read the map")
    if os.path.exists("/dev/zero"):
        with pytest.raises(CityshadeError, match="not a regular file") as info:
            load_map("/dev/zero")
        assert info.value.exit_code == 2
    fifo = tmp_path / "pipe.osm"
    os.mkfifo(fifo)
    _refused(fifo, "not a regular file")


def test_truncated_pbf_is_refused(tmp_path, helsinki_pbf):
    path = tmp_path / "cut.osm.pbf"
    path.write_bytes(helsinki_pbf.read_bytes()[:300_000])
    _refused(path, "not a readable OpenStreetMap file", "PBF error")


def test_a_huge_outline_loads_simplified(tmp_path):
    angles = np.linspace(0.0, 2.0 * np.pi, 20_000, endpoint=False)
    ring = np.stack([24.0 + 0.001 * np.cos(angles), 60.0 + 0.0005 * np.sin(angles)], axis=1).tolist()
    path = tmp_path / "round.geojson"
    path.write_text(
        json.dumps(
            {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [ring + ring[:1]]}}
        )
    )
    (building,) = load_map(path).buildings
    assert len(building.outline.exterior.coords) < 5_000
    assert building.footprint_area == pytest.approx(np.pi * 55.7 * 55.6, rel=0.02)


def _geojson(tmp_path, *geometries_or_features, name="bad.geojson") -> Path:
    features = [
        g if g is not None and g.get("type") == "Feature" else {"type": "Feature", "properties": {}, "geometry": g}
        for g in geometries_or_features
    ]
    path = tmp_path / name
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}, allow_nan=True))
    return path


GOOD = {"type": "Polygon", "coordinates": [[[24.0, 60.0], [24.0004, 60.0], [24.0004, 60.0002], [24.0, 60.0]]]}


@pytest.mark.parametrize(
    "geometry, why",
    [
        ({"type": "Polygon", "coordinates": []}, "Polygon coordinates are not rings"),
        ({"type": "Polygon", "coordinates": None}, "Polygon coordinates are not rings"),
        ({"type": "Polygon", "coordinates": [24.0, 60.0, 24.1, 60.1]}, "Polygon coordinates are not rings"),
        ({"type": "Polygon", "coordinates": [[24.0, 60.0, 24.1]]}, "Polygon coordinates are not rings"),
        ({"type": "Polygon", "coordinates": [[["a", "b"], [1, 2], [3, 4]]]}, "Polygon coordinates are not rings"),
        ({"type": "MultiPolygon", "coordinates": [[]]}, "MultiPolygon coordinates are not rings"),
        (
            {
                "type": "Polygon",
                "coordinates": [[[24.0, 60.0], [float("nan"), 60.0], [24.0004, 60.0002], [24.0, 60.0]]],
            },
            "longitude/latitude not finite or out of range",
        ),
        (
            {
                "type": "Polygon",
                "coordinates": [[[24.0, 60.0], [float("inf"), 60.0], [24.0004, 60.0002], [24.0, 60.0]]],
            },
            "longitude/latitude not finite or out of range",
        ),
        (
            {"type": "Polygon", "coordinates": [[[24.0, 60.0], [1e308, 60.0], [24.0004, 60.0002], [24.0, 60.0]]]},
            "longitude/latitude not finite or out of range",
        ),
        ({"type": "GeometryCollection", "geometries": [GOOD]}, "geometry type 'GeometryCollection' is not read"),
        (None, "no geometry"),
    ],
)
def test_geojson_geometry_that_cannot_be_read_is_skipped_and_counted(tmp_path, geometry, why):
    data = load_map(_geojson(tmp_path, GOOD, geometry))
    assert len(data.buildings) == 1
    ((what, reason),) = data.report.skipped
    assert reason.startswith(why)
    assert data.report.examples[(what, reason)] == "feature/1"


def test_geojson_self_touching_and_unclosed_rings_are_repaired(tmp_path):
    touching = [[24.0, 60.0], [24.0004, 60.0], [24.0004, 60.0002], [24.0002, 60.0], [24.0, 60.0002], [24.0, 60.0]]
    unclosed = [[24.001, 60.0], [24.0014, 60.0], [24.0014, 60.0002], [24.001, 60.0002]]
    data = load_map(
        _geojson(
            tmp_path, {"type": "Polygon", "coordinates": [touching]}, {"type": "Polygon", "coordinates": [unclosed]}
        )
    )
    assert len(data.buildings) == 3 and all(b.outline.is_valid for b in data.buildings)
    ((what, why),) = [key for key in data.report.repaired if key[0] == "building"]
    assert why.startswith("invalid outline") and data.report.examples[(what, why)] == "feature/0"
    assert data.report.examples[("feature", "ring not closed, closed")] == "feature/1"


def test_json_above_the_size_limit_is_refused(tmp_path, monkeypatch):
    from cityshade.maps import _load

    monkeypatch.setattr(_load, "MAX_JSON_BYTES", 100)
    _refused(_geojson(tmp_path, GOOD), "above the 100-byte limit")


def test_cityjson_has_its_own_smaller_size_limit(tmp_path, monkeypatch):
    from cityshade.maps import _load

    monkeypatch.setattr(_load, "MAX_CITYJSON_BYTES", 100)
    city = tmp_path / "big.city.json"
    city.write_text(json.dumps({"type": "CityJSON", "CityObjects": {}, "vertices": [[0, 0, 0]] * 20}))
    _refused(city, "bytes of CityJSON is above the 100-byte limit; split the file into tiles")
    sequence = tmp_path / "big.city.jsonl"  # streamed: no cap on the file, one on each line
    sequence.write_text('{"type":"CityJSON","version":"2.0","CityObjects":{},"vertices":[]}\n' + " " * 200 + "{}\n")
    _refused(sequence, "a line of over 100 characters is no CityJSONSeq feature")
    assert len(load_map(_geojson(tmp_path, GOOD)).buildings) == 1  # GeoJSON keeps the 1 GiB limit


def test_geojson_with_nothing_usable_exits_2_with_the_reason(tmp_path):
    path = _geojson(tmp_path, {"type": "Polygon", "coordinates": []})
    _refused(path, "nothing usable", "Polygon coordinates are not rings", "feature/0")


def test_geojson_thousand_digit_integers_drop_their_feature(tmp_path):
    path = tmp_path / "digits.geojson"
    big = "9" * 5000
    path.write_text(
        '{"type": "FeatureCollection", "features": ['
        + json.dumps({"type": "Feature", "properties": {}, "geometry": GOOD})
        + ', {"type": "Feature", "properties": {"height": '
        + big
        + '}, "geometry": '
        '{"type": "Polygon", "coordinates": [[[24.001, 60], [' + big + ", 60], [24.0014, 60.0002], "
        "[24.001, 60]]]}}]}"
    )
    data = load_map(path)
    assert len(data.buildings) == 1
    assert data.report.examples[("building", "longitude/latitude not finite or out of range")] == "feature/1"


def test_geojson_properties_that_are_lists_or_strings_are_ignored_and_counted(tmp_path):
    path = _geojson(
        tmp_path,
        {"type": "Feature", "properties": "tall", "geometry": GOOD},
        {"type": "Feature", "properties": {"height": [1, 2], "building:levels": 3}, "geometry": GOOD},
    )
    data = load_map(path)
    assert [b.levels for b in data.buildings] == [None, 3.0]
    assert data.report.fallbacks == {
        ("properties", "not an object (ignored)"): 1,
        ("height", "a list or object where a value belongs (ignored)"): 1,
    }


@pytest.mark.parametrize("depth", [70, 5000])
@pytest.mark.parametrize("name, kind", [("deep.geojson", "FeatureCollection"), ("deep.city.json", "CityJSON")])
def test_json_nested_beyond_the_limit_is_one_line(tmp_path, depth, name, kind):
    deep = tmp_path / name
    deep.write_text(f'{{"type": "{kind}", "features": ' + "[" * depth + "]" * depth + "}")
    _refused(deep, "nested too deeply to be a map (arrays and objects nested more than 64 levels deep")


def test_json_nested_within_the_limit_loads(tmp_path):
    nested = "[" * 60 + "]" * 60
    path = _geojson(tmp_path, {"type": "Feature", "properties": {"notes": json.loads(nested)}, "geometry": GOOD})
    assert len(load_map(path).buildings) == 1


def test_invalid_json_is_one_line(tmp_path):
    broken = tmp_path / "broken.geojson"
    broken.write_text('{"type": "FeatureCollection",\n "features": [}')
    _refused(broken, f"{broken}:2:15: error: invalid JSON")
    other = tmp_path / "other.json"
    other.write_text('{"hello": 1}')
    _refused(other, "not GeoJSON")


def test_cityjson_with_broken_boundaries_skips_the_object(tmp_path):
    path = tmp_path / "broken.city.json"
    path.write_text(
        json.dumps(
            {
                "type": "CityJSON",
                "version": "2.0",
                "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]],
                "CityObjects": {
                    "a": {
                        "type": "Building",
                        "geometry": [{"type": "MultiSurface", "lod": "1", "boundaries": [[[0, 1, 99]]]}],
                    }
                },
            }
        )
    )
    _refused(path, "nothing usable", "CityObject/a", "vertex index out of range")


def test_cityjson_coordinates_that_overflow_are_skipped_without_a_warning(tmp_path):
    import warnings

    path = tmp_path / "huge.city.json"
    face = {"type": "MultiSurface", "lod": "1", "boundaries": [[[0, 1, 2]], [[0, 2, 3]]]}
    document = {
        "type": "CityJSON",
        "transform": {"scale": [1e308] * 3, "translate": [0, 0, 0]},
        "CityObjects": {"b": {"type": "Building", "geometry": [face]}},
        "vertices": [[0, 0, 0], [10, 0, 0], [10, 10, 5], [0, 10, 5]],
    }
    path.write_text(json.dumps(document))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # a warning would reach stderr before the one line
        _refused(path, "nothing usable in the map: 2 surface skipped, vertex not three finite numbers")


def test_the_content_decides_the_format_not_the_name(tmp_path, silent_pbf):
    xml = tmp_path / "really_xml.pbf"
    xml.write_bytes((Path(__file__).parents[1] / "data" / "maps" / "tagged.osm").read_bytes())
    pbf = tmp_path / "really_pbf.osm"
    pbf.write_bytes(silent_pbf.read_bytes())
    assert len(load_map(xml).buildings) == 5 and len(load_map(pbf).buildings) > 2000


@pytest.mark.parametrize("module, suffix", [("gzip", ".osm.gz"), ("bz2", ".osm.bz2")])
def test_compressed_xml_is_read_and_checked_like_plain_xml(tmp_path, module, suffix):
    import importlib

    compress = importlib.import_module(module).compress
    plain = (Path(__file__).parents[1] / "data" / "maps" / "tagged.osm").read_bytes()
    path = tmp_path / f"tagged{suffix}"
    path.write_bytes(compress(plain))
    assert len(load_map(path).buildings) == 5
    bomb = tmp_path / f"bomb{suffix}"
    bomb.write_bytes(compress(b'<?xml version="1.0"?>\n<!DOCTYPE osm [<!ENTITY a "aaaa">]>\n<osm version="0.6"/>'))
    _refused(bomb, "declares a document type or entities")
    cut = tmp_path / f"cut{suffix}"
    cut.write_bytes(compress(plain)[:200])
    _refused(cut, "not a readable OpenStreetMap file")


def _gzip_of(path: Path, head: bytes, unit: bytes, count: int) -> Path:
    """`head` and `count` times `unit`, gzip-compressed chunk by chunk: megabytes in, kilobytes out."""
    with gzip.open(path, "wb") as out:
        out.write(head)
        for _ in range(count):
            out.write(unit)
    return path


XML_HEAD = b'<?xml version="1.0"?>\n<osm version="0.6">\n'


def test_a_gzip_bomb_of_one_long_line_is_refused_at_the_line_cap(tmp_path):
    bomb = _gzip_of(tmp_path / "bomb.osm.gz", XML_HEAD + b"<!-- ", b"a" * (1 << 20), 17)  # 17 MiB, 17 KB packed
    assert bomb.stat().st_size < 100_000
    _refused(bomb, f"line 3 is longer than the {16 << 20} bytes", "one element a line")


def test_a_gzip_bomb_is_refused_at_the_uncompressed_cap(tmp_path):
    from cityshade.maps.testing import check_xml

    bomb = _gzip_of(tmp_path / "bomb.osm.gz", XML_HEAD, b"<!-- padding -->\n" * 4096, 64)  # 4.25 MiB
    with pytest.raises(CityshadeError) as info:
        check_xml(bomb, "osm.gz", limits=(1 << 20, 1 << 16))
    assert f"more than the {1 << 20} bytes a map may have (uncompressed)" in str(info.value)
    check_xml(bomb, "osm.gz", limits=(5 << 20, 1 << 16))  # within the caps it passes the scan


def test_a_file_that_cannot_be_opened_is_one_line(tmp_path, monkeypatch):
    import builtins

    path = tmp_path / "locked.osm"
    path.write_text("<osm/>")
    real_open = builtins.open

    def denied(file, *args, **kwargs):  # what chmod 000 does for anyone but root
        if str(file) == str(path):
            raise PermissionError(13, "Permission denied")
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", denied)
    _refused(path, "cannot read the map (Permission denied)")
