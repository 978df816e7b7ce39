"""Fuzzing the map readers: whatever the bytes, `load_map` returns a map or raises one line with exit code 2.

The budget is small in the normal suite; `CITYSHADE_FUZZ_EXAMPLES=100000 pytest tests/maps/test_maps_read_fuzz.py`
runs a long campaign (about an hour on 2 cores; 1,500 took 53 s).
"""

from __future__ import annotations

import json
import os
import random
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fuzzing import loads_or_one_line

EXAMPLES = int(os.environ.get("CITYSHADE_FUZZ_EXAMPLES", "60"))
DATA = Path(__file__).parents[1] / "data" / "maps"


def _mutated(data: bytes, rng: random.Random) -> bytes:
    """A few byte flips, cuts and insertions."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        at = rng.randrange(len(data))
        roll = rng.random()
        if roll < 0.4:
            data[at] = rng.randrange(256)
        elif roll < 0.7:
            del data[at : at + rng.randint(1, 64)]
        else:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
    return bytes(data)


@pytest.mark.parametrize("source, suffix", [("xml", ".osm"), ("pbf", ".osm.pbf"), ("geojson", ".geojson")])
def test_mutated_files(tmp_path, helsinki_pbf, source, suffix):
    original = {
        "xml": (DATA / "tagged.osm").read_bytes(),
        "pbf": helsinki_pbf.read_bytes()[:200_000],
        "geojson": json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    {
                        "type": "Feature",
                        "properties": {"height": "12", "roof:shape": "gabled"},
                        "geometry": {
                            "type": "Polygon",
                            "coordinates": [[[24.0, 60.0], [24.001, 60.0], [24.001, 60.001], [24.0, 60.0]]],
                        },
                    }
                ],
            }
        ).encode(),
    }[source]
    rng = random.Random(source)
    path = tmp_path / f"fuzz{suffix}"
    for _ in range(EXAMPLES):
        path.write_bytes(_mutated(original, rng))
        loads_or_one_line(path)


_numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**30), 10**30),
    st.sampled_from([24.0, 60.0, 24.0004, 60.0002, 1e308, -0.0]),
)
_values = st.recursive(
    st.one_of(_numbers, st.text(max_size=8), st.none(), st.booleans()),
    lambda inner: st.lists(inner, max_size=5),
    max_leaves=30,
)
_geometry = st.fixed_dictionaries(
    {
        "type": st.sampled_from(
            [
                "Polygon",
                "MultiPolygon",
                "LineString",
                "MultiLineString",
                "Point",
                "MultiPoint",
                "GeometryCollection",
                "Circle",
                None,
            ]
        ),
        "coordinates": _values,
    }
)
_properties = st.one_of(
    st.dictionaries(
        st.sampled_from(
            ["height", "building", "building:levels", "roof:shape", "natural", "highway", "roof:colour", "min_height"]
        ),
        _values,
        max_size=4,
    ),
    _values,
)
_feature = st.fixed_dictionaries(
    {"type": st.just("Feature"), "geometry": st.one_of(_geometry, st.none(), _values), "properties": _properties}
)


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(features=st.lists(_feature, max_size=4))
def test_generated_geojson(tmp_path, features):
    path = tmp_path / "generated.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    loads_or_one_line(path)


_indices = st.recursive(st.integers(-2, 12), lambda inner: st.lists(inner, max_size=6), max_leaves=40)
_city_geometry = st.fixed_dictionaries(
    {
        "type": st.sampled_from(["Solid", "MultiSurface", "CompositeSurface", "MultiSolid", "CompositeSolid", "Point"]),
        "lod": st.one_of(st.sampled_from(["1", "2.2", 2]), _values),
        "boundaries": st.one_of(_indices, _values),
    },
    optional={
        "semantics": st.fixed_dictionaries(
            {
                "surfaces": st.lists(
                    st.fixed_dictionaries({"type": st.sampled_from(["RoofSurface", "WallSurface", "GroundSurface"])}),
                    max_size=3,
                ),
                "values": st.one_of(_indices, _values),
            }
        )
    },
)
_city_object = st.fixed_dictionaries(
    {
        "type": st.sampled_from(["Building", "BuildingPart", "Road"]),
        "geometry": st.one_of(st.lists(_city_geometry, max_size=2), _values),
    },
    optional={
        "children": st.lists(st.sampled_from(["a", "b", "c"]), max_size=2),
        "parents": st.lists(st.sampled_from(["a", "b", "c"]), max_size=2),
        "attributes": _properties,
    },
)
_vertices = st.one_of(
    st.lists(st.tuples(_numbers, _numbers, _numbers), min_size=1, max_size=12),
    _values,
    st.just([[0, 0, 0], [10, 0, 0], [10, 8, 0], [0, 8, 0], [0, 0, 6], [10, 0, 6], [10, 8, 6], [0, 8, 6], [5, 4, 9]]),
)


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    objects=st.dictionaries(st.sampled_from(["a", "b", "c"]), _city_object, max_size=3),
    vertices=_vertices,
    transform=st.one_of(st.none(), st.fixed_dictionaries({"scale": _values, "translate": _values})),
)
def test_generated_cityjson(tmp_path, objects, vertices, transform):
    document = {"type": "CityJSON", "version": "2.0", "CityObjects": objects, "vertices": vertices}
    if transform is not None:
        document["transform"] = transform
    path = tmp_path / "generated.city.json"
    path.write_text(json.dumps(document))
    loads_or_one_line(path)


_coordinate = st.one_of(
    st.floats(-100, 100).map(lambda v: f"{v:.7f}"),
    st.sampled_from(["60.0", "60.0002", "24.0", "24.0004", "", "nan", "1e5", "-0", "+1"]),
)
_tag = st.tuples(
    st.sampled_from(
        [
            "building",
            "building:part",
            "height",
            "natural",
            "highway",
            "type",
            "roof:shape",
            "landuse",
            "building:levels",
            "area",
            "railway",
            "roof:direction",
        ]
    ),
    st.sampled_from(
        [
            "yes",
            "multipolygon",
            "tree",
            "water",
            "coastline",
            "tree_row",
            "primary",
            "street_lamp",
            "roof",
            "12",
            "-5",
            "tall",
            "N",
            "gabled",
            "grass",
            "tram",
            "&amp;",
        ]
    ),
)


def _tags_xml(tags) -> str:
    return "".join(f'<tag k="{k}" v="{v}"/>' for k, v in tags)


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    nodes=st.lists(st.tuples(st.integers(1, 8), _coordinate, _coordinate, st.lists(_tag, max_size=2)), max_size=10),
    ways=st.lists(
        st.tuples(st.integers(1, 4), st.lists(st.integers(1, 9), max_size=8), st.lists(_tag, max_size=3)), max_size=4
    ),
    relations=st.lists(
        st.tuples(
            st.lists(st.tuples(st.integers(1, 5), st.sampled_from(["outer", "inner", ""])), max_size=4),
            st.lists(_tag, max_size=3),
        ),
        max_size=2,
    ),
)
def test_generated_osm_xml(tmp_path, nodes, ways, relations):
    body = [f'<node id="{i}" lat="{lat}" lon="{lon}">{_tags_xml(tags)}</node>' for i, lat, lon, tags in nodes]
    body += [
        f'<way id="{i}">' + "".join(f'<nd ref="{r}"/>' for r in refs) + _tags_xml(tags) + "</way>"
        for i, refs, tags in ways
    ]
    body += [
        f'<relation id="{i + 1}">'
        + "".join(f'<member type="way" ref="{r}" role="{role}"/>' for r, role in members)
        + _tags_xml(tags)
        + "</relation>"
        for i, (members, tags) in enumerate(relations)
    ]
    path = tmp_path / "generated.osm"
    path.write_text('<?xml version="1.0" encoding="UTF-8"?>\n<osm version="0.6">\n' + "\n".join(body) + "\n</osm>\n")
    loads_or_one_line(path)
