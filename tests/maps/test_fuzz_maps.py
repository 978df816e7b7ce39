"""Structure-aware fuzzers for the map readers (OpenStreetMap XML, .osm.gz, .osm.pbf, CityJSON) and the CGA
importer: whatever they are given, they load it or refuse it with one line (exit code 2), never a
traceback, and reading CityJSON stays within its documented memory factor.

`make test` runs the small variants (a few seconds); `make fuzz` the long ones (docs/robustness.md).
"""

from __future__ import annotations

import gzip
import json
import tracemalloc
from pathlib import Path

import osmium
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cityshade.grammar import CgaError, GrammarError, loads, translate
from cityshade.maps import load_map
from fuzzing import LARGE, SMALL, for_a_while, loads_or_one_line

# ------------------------------------------------------------------ OpenStreetMap XML

coordinate_text = st.one_of(
    st.floats(-200.0, 200.0, allow_nan=False).map(lambda v: f"{v:.7f}"),
    st.sampled_from(["nan", "inf", "-inf", "1e308", "60.0e1", "", "abc", "90.0000001", "--1"]),
)
tags = st.dictionaries(
    st.sampled_from(["building", "building:part", "height", "highway", "natural", "roof:shape", "min_height", "area"]),
    st.sampled_from(["yes", "no", "tree", "residential", "gabled", "12", "-3", "1e999", "nan", "", "&amp;"]),
    max_size=4,
)


def _tag_xml(values: dict) -> str:
    return "".join(f'<tag k="{k}" v="{v}"/>' for k, v in values.items())


@st.composite
def osm_documents(draw) -> bytes:
    count = draw(st.integers(0, 12))
    nodes = [
        f'<node id="{i}" lat="{draw(coordinate_text)}" lon="{draw(coordinate_text)}">{_tag_xml(draw(tags))}</node>'
        for i in range(1, count + 1)
    ]
    ways = []
    for way in range(draw(st.integers(0, 4))):
        refs = draw(st.lists(st.integers(0, count + 2), max_size=8))
        if refs and draw(st.booleans()):
            refs.append(refs[0])  # closed
        members = "".join(f'<nd ref="{r}"/>' for r in refs)
        ways.append(f'<way id="{100 + way}">{members}{_tag_xml(draw(tags))}</way>')
    relations = [
        f'<relation id="{200 + r}"><member type="way" ref="{draw(st.integers(99, 104))}" role="outer"/>'
        f'<tag k="type" v="multipolygon"/>{_tag_xml(draw(tags))}</relation>'
        for r in range(draw(st.integers(0, 2)))
    ]
    body = "\n".join(nodes + ways + relations)
    text = f'<?xml version="1.0" encoding="UTF-8"?>\n<osm version="0.6">\n{body}\n</osm>\n'
    cut = draw(st.one_of(st.none(), st.integers(0, len(text))))
    return text[:cut].encode("utf-8")


def check_osm(document: bytes, packed: bool, folder: Path) -> None:
    path = folder / ("fuzz.osm.gz" if packed else "fuzz.osm")
    path.write_bytes(gzip.compress(document) if packed else document)
    loads_or_one_line(path)


# ------------------------------------------------------------------ OpenStreetMap PBF

location = st.tuples(st.floats(-200.0, 200.0, allow_nan=False), st.floats(-100.0, 100.0, allow_nan=False))


@st.composite
def pbf_files(draw) -> tuple[list, bytes | None]:
    """Nodes, ways and relations as pyosmium writes them (out-of-range locations, ways to missing
    nodes, relations to missing ways), and byte edits to make of the written file: (offset, byte)
    pairs and a length to cut it to, or none."""
    count = draw(st.integers(0, 10))
    objects = [osmium.osm.mutable.Node(id=i, location=draw(location), tags=draw(tags)) for i in range(1, count + 1)]
    for way in range(draw(st.integers(0, 4))):
        refs = draw(st.lists(st.integers(1, count + 2), max_size=8))
        if refs and draw(st.booleans()):
            refs.append(refs[0])  # closed
        objects.append(osmium.osm.mutable.Way(id=100 + way, nodes=refs, tags=draw(tags)))
    for relation in range(draw(st.integers(0, 2))):
        members = [("w", draw(st.integers(99, 104)), draw(st.sampled_from(["outer", "inner", "part"])))]
        objects.append(
            osmium.osm.mutable.Relation(id=200 + relation, members=members, tags={"type": "multipolygon", **draw(tags)})
        )
    edits = draw(st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 255)), max_size=4))
    cut = draw(st.one_of(st.none(), st.integers(0, 10**6)))
    return objects, (edits, cut)


def check_pbf(drawn, folder: Path) -> None:
    objects, (edits, cut) = drawn
    path = folder / "fuzz.osm.pbf"
    path.unlink(missing_ok=True)
    writer = osmium.SimpleWriter(str(path))
    try:
        for thing in objects:
            {"Node": writer.add_node, "Way": writer.add_way, "Relation": writer.add_relation}[type(thing).__name__](
                thing
            )
    finally:
        writer.close()
    data = bytearray(path.read_bytes())
    for offset, value in edits:  # a damaged blob: header, sizes or compressed data
        data[offset % len(data)] = value
    path.write_bytes(bytes(data[:cut]))
    loads_or_one_line(path)


# ------------------------------------------------------------------ CityJSON

index = st.one_of(st.integers(-2, 12), st.sampled_from([1.5, "3", None, [0], 10**20]))
ring = st.lists(index, min_size=0, max_size=6)
surface = st.lists(ring, min_size=1, max_size=2)
shell = st.lists(surface, min_size=0, max_size=5)
boundaries = {
    "MultiSurface": shell,
    "CompositeSurface": shell,
    "Solid": st.lists(shell, min_size=0, max_size=2),
    "MultiSolid": st.lists(st.lists(shell, max_size=2), max_size=2),
    "CompositeSolid": st.lists(st.lists(shell, max_size=2), max_size=2),
    "Point": st.just([0]),
}
number = st.one_of(st.floats(-1e4, 1e4, allow_nan=False), st.sampled_from([0, 1e308, -1e308, 1e-300]))


@st.composite
def geometries(draw) -> dict:
    kind = draw(st.sampled_from(sorted(boundaries)))
    geometry = {"type": kind, "lod": draw(st.sampled_from(["1", "2", "2.2", 1, "x", None])), "boundaries": None}
    geometry["boundaries"] = draw(boundaries[kind])
    if draw(st.booleans()):
        surfaces = [
            {"type": t} for t in draw(st.lists(st.sampled_from(["GroundSurface", "RoofSurface", "WallSurface"])))
        ]
        values = draw(st.one_of(st.lists(st.one_of(st.integers(-1, 4), st.none())), st.lists(st.lists(index))))
        geometry["semantics"] = {"surfaces": surfaces, "values": values}
    return geometry


@st.composite
def cityjson_documents(draw) -> str:
    names = [f"o{i}" for i in range(draw(st.integers(0, 5)))]
    objects = {}
    for name in names:
        obj = {"type": draw(st.sampled_from(["Building", "BuildingPart", "Road", "TINRelief"]))}
        obj["geometry"] = draw(st.lists(geometries(), max_size=2))
        for link in ("parents", "children"):
            if draw(st.booleans()):
                obj[link] = draw(st.lists(st.sampled_from(names + ["missing"]), max_size=2))
        if draw(st.booleans()):
            obj["attributes"] = draw(st.dictionaries(st.sampled_from(["roof:shape", "height", "x"]), number | tags))
        objects[name] = obj
    document = {
        "type": "CityJSON",
        "version": draw(st.sampled_from(["1.0", "1.1", "2.0"])),
        "CityObjects": objects,
        "vertices": draw(st.lists(st.lists(number, min_size=3, max_size=3), max_size=12) | st.just([[1, 2]])),
    }
    if draw(st.booleans()):
        document["transform"] = {"scale": draw(st.lists(number, max_size=3)), "translate": [85000.0, 446000.0, 0.0]}
    if draw(st.booleans()):
        code = draw(st.sampled_from(["7415", "28992", "4326", "999999", "5709", "3857"]))
        document["metadata"] = {"referenceSystem": f"https://www.opengis.net/def/crs/EPSG/0/{code}"}
    return json.dumps(document)


def check_cityjson(text: str, folder: Path) -> None:
    path = folder / "fuzz.city.json"
    path.write_text(text)
    loads_or_one_line(path)


# ------------------------------------------------------------------ CGA rule files

cga_value = st.one_of(
    st.floats(-50, 50, allow_nan=False).map(lambda v: f"{v:g}"),
    st.sampled_from(["h", "w * 2", "-" * 300 + "1", "(" * 40 + "1" + ")" * 40, '"brick.jpg"', "rand(1, 2)"]),
)
cga_size = st.tuples(st.sampled_from(["", "~", "'"]), cga_value).map("".join)
cga_names = st.sampled_from(["Facade", "Floor", "Tile", "Window", "Wall", "Door", "Missing"])


@st.composite
def cga_bodies(draw, depth: int = 0) -> str:
    choice = draw(st.integers(0, 5 if depth < 3 else 2))
    if choice == 0:
        return f'color("{draw(st.sampled_from(["#ff0000", "#abc", "red", "#zz", ""]))}")'
    if choice == 1:
        return draw(st.sampled_from(['texture("brick.jpg")', "NIL", 'i("door.obj")', "extrude(3)"]))
    if choice == 2:
        return draw(cga_names)
    if choice == 3:
        parts = [f"{draw(cga_size)} : {draw(cga_bodies(depth + 1))}" for _ in range(draw(st.integers(1, 3)))]
        group = " | ".join(parts)
        return f"split({draw(st.sampled_from(['x', 'y', 'z']))}) {{ {group} }}" + ("*" if draw(st.booleans()) else "")
    if choice == 4:
        return f"case split.index == {draw(cga_value)} : {draw(cga_bodies(depth + 1))} else : {draw(cga_names)}"
    return f"{draw(cga_value)}% : {draw(cga_bodies(depth + 1))} else : NIL"


@st.composite
def cga_files(draw) -> str:
    lines = [f"attr {n} = {draw(cga_value)}" for n in draw(st.lists(st.sampled_from(["h", "w"]), max_size=2))]
    for name in draw(st.lists(cga_names, min_size=1, max_size=4)):
        lines.append(f"{name} --> {draw(cga_bodies())}")
    text = "\n".join(lines) + "\n"
    return text[: draw(st.integers(0, len(text)))] if draw(st.integers(0, 4)) == 0 else text


def check_cga(text: str) -> None:
    try:
        translation = translate(text, "fuzz.cga")
    except CgaError as exc:
        assert str(exc).startswith("fuzz.cga:") and "error:" in str(exc), str(exc)
        return
    try:  # what `grammar import` checks before writing: a located GrammarError is the only failure
        loads(translation.text, "fuzz.grammar")
    except GrammarError as exc:
        assert str(exc).startswith("fuzz.grammar:"), str(exc)


# ------------------------------------------------------------------ memory


def _blocks(count: int) -> str:
    """A CityJSON of `count` LoD2 boxes with semantic surfaces, like a published tile."""
    objects, vertices = {}, []
    for i in range(count):
        x, y, base = (i % 40) * 20, (i // 40) * 20, len(vertices)
        vertices += [[x + dx, y + dy, z] for dx, dy in ((0, 0), (10, 0), (10, 10), (0, 10)) for z in (0, 12)]
        faces = [(0, 6, 4, 2), (1, 3, 5, 7), (0, 2, 3, 1), (2, 4, 5, 3), (4, 6, 7, 5), (6, 0, 1, 7)]
        semantics = {"surfaces": [{"type": t} for t in ("GroundSurface", "RoofSurface", "WallSurface")]}
        semantics["values"] = [[0, 1, 2, 2, 2, 2]]
        shell = [[[base + k for k in face]] for face in faces]
        geometry = {"type": "Solid", "lod": "2.2", "boundaries": [shell], "semantics": semantics}
        objects[f"b{i}"] = {"type": "Building", "geometry": [geometry]}
    return json.dumps({"type": "CityJSON", "version": "2.0", "CityObjects": objects, "vertices": vertices})


def test_cityjson_reading_stays_within_its_documented_memory_factor(tmp_path):
    from cityshade.maps.testing import MAX_CITYJSON_BYTES

    path = tmp_path / "blocks.city.json"
    path.write_text(_blocks(600))
    tracemalloc.start()
    try:
        assert len(load_map(path).buildings) == 600
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    factor = peak / path.stat().st_size
    assert factor < 30, factor  # docs/robustness.md: about 24; the cap keeps 30 x 256 MiB under 8 GiB
    assert MAX_CITYJSON_BYTES * 30 <= 8 << 30


# ------------------------------------------------------------------ small variants (make test)


@SMALL
@given(osm_documents(), st.booleans())
def test_osm_xml_and_gzip_small(tmp_path_factory, document, packed):
    check_osm(document, packed, tmp_path_factory.mktemp("osm"))


@SMALL
@given(pbf_files())
def test_osm_pbf_small(tmp_path_factory, drawn):
    check_pbf(drawn, tmp_path_factory.mktemp("pbf"))


@SMALL
@given(cityjson_documents())
def test_cityjson_small(tmp_path_factory, text):
    check_cityjson(text, tmp_path_factory.mktemp("cityjson"))


@SMALL
@given(cga_files())
def test_cga_small(text):
    check_cga(text)


# ------------------------------------------------------------------ the long runs (make fuzz)


@pytest.mark.fuzz
def test_osm_xml_and_gzip_long(tmp_path_factory):
    folder = tmp_path_factory.mktemp("osm")
    for_a_while(LARGE(given(osm_documents(), st.booleans())(lambda d, packed: check_osm(d, packed, folder))))


@pytest.mark.fuzz
def test_osm_pbf_long(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pbf")
    for_a_while(LARGE(given(pbf_files())(lambda drawn: check_pbf(drawn, folder))))


@pytest.mark.fuzz
def test_cityjson_long(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cityjson")
    for_a_while(LARGE(given(cityjson_documents())(lambda text: check_cityjson(text, folder))))


@pytest.mark.fuzz
def test_cga_long():
    for_a_while(LARGE(given(cga_files())(check_cga)))
