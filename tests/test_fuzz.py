"""Fuzzers: mutated grammars and random footprints. A small budget runs with every `make test`;
`make fuzz` runs the `fuzz`-marked tests for CITYSHADE_FUZZ_SECONDS seconds each (default 60;
docs/robustness.md). Every failure hypothesis finds is shrunk and replayed from its database."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st

from cityshade.assets import tile_array
from cityshade.errors import CityshadeError
from cityshade.grammar import (
    LIBRARY_STYLES,
    GrammarError,
    compile_grammars,
    evaluate_facade,
    library_path,
    loads,
    seed_vector,
)
from cityshade.maps import load_map, map_city
from cityshade.scene import SURFACE_ROOF, BuildingMass, building_vertices
from fuzzing import LARGE, SMALL, for_a_while

# ------------------------------------------------------------------ grammar mutations

SEEDS = [library_path(f"{style}.grammar").read_text(encoding="utf-8") for style in LIBRARY_STYLES]
TOKENS = [
    "->",
    "(",
    ")",
    ",",
    ";",
    "\n",
    "\f",
    "\r",
    "\t",
    "#",
    "Rep:wall1",
    "Fit>door1",
    "Rep:nosuch",
    "Abs",
    "Rel",
    "Color",
    "SplitX",
    "SplitY",
    "RepeatX",
    "Rand",
    "RandUni",
    "RandStack",
    "Layer",
    "Skip",
    "SkipMask",
    "Intrusion",
    "Mat",
    "MatAlpha",
    "S",
    "A.B",
    'use "brick.grammar" as B\n',
    'use "/etc/passwd" as P\n',
    "0",
    "-1",
    "1e999",
    "65504",
    "65505",
    "1e-30",
    "0.5",
    "99999999999999999999",
    ".",
    "é",
    "\x00",
]
TILES = tile_array(32)


@st.composite
def mutated_grammars(draw) -> str:
    text = draw(st.sampled_from(SEEDS))
    for _ in range(draw(st.integers(1, 6))):
        at = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["insert", "delete", "replace_number", "duplicate_line", "text"]))
        if kind == "insert":
            text = text[:at] + draw(st.sampled_from(TOKENS)) + text[at:]
        elif kind == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 20)) :]
        elif kind == "replace_number":
            numbers = list(re.finditer(r"\d+(\.\d+)?", text))
            if numbers:
                match = draw(st.sampled_from(numbers))
                value = draw(
                    st.one_of(
                        st.floats(allow_nan=False, allow_infinity=False, width=64), st.integers(-(10**30), 10**30)
                    )
                )
                text = text[: match.start()] + repr(value).replace("+", "") + text[match.end() :]
        elif kind == "duplicate_line":
            lines = text.split("\n")
            line = draw(st.integers(0, len(lines) - 1))
            text = "\n".join(lines[: line + 1] + lines[line:])
        else:
            text = text[:at] + draw(st.text(max_size=8)) + text[at:]
    return text


def check_grammar(text: str):
    """Refused with a located first line inside the text, or evaluated by the numpy evaluator."""
    try:
        grammar = loads(text, "fuzz.grammar")
        compiled = compile_grammars({"g": grammar})
    except GrammarError as exc:
        first = str(exc).splitlines()[0]
        match = re.match(r"^fuzz\.grammar:(\d+):(\d+): error: ", first)
        assert match, first
        assert 1 <= int(match.group(1)) <= text.count("\n") + 1, first
        return
    result = evaluate_facade(compiled, compiled.address("g"), (9.0, 7.0), (9, 7), seed_vector(5), TILES)
    assert np.all(np.isfinite(result.color)) and result.label.shape == (7, 9)


@SMALL
@given(mutated_grammars())
def test_mutated_grammars_small(text):
    check_grammar(text)


# ------------------------------------------------------------------ footprints

coordinate = st.floats(-200.0, 200.0, allow_nan=False, allow_infinity=False)


@st.composite
def outlines(draw) -> np.ndarray:
    """Simple polygons (star-shaped about a centre: angles sorted, random radii), sometimes with
    near-duplicate or collinear corners."""
    n = draw(st.integers(3, 60))
    angles = np.sort(
        np.asarray(draw(st.lists(st.floats(0, 2 * math.pi, exclude_max=True), min_size=n, max_size=n, unique=True)))
    )
    radii = np.asarray(draw(st.lists(st.floats(0.5, 80.0), min_size=n, max_size=n)))
    points = np.stack([radii * np.cos(angles), radii * np.sin(angles)], 1)
    return points - points.min(axis=0)


def check_outline(points: np.ndarray):
    polygon = shapely.Polygon(points)
    if not polygon.is_valid or polygon.area < 1e-3:
        return
    mass = BuildingMass("prism", (0.0, 0.0), tuple(map(tuple, points)), 12.0)
    with np.errstate(invalid="raise", divide="raise"):  # a NaN normal or a division by a zero-length edge
        vertices = building_vertices(mass, 0)
    for field in ("position", "normal", "facade"):
        assert np.all(np.isfinite(vertices[field])), field
    roof = vertices["local"][vertices["ids"][:, 1] == SURFACE_ROOF][:, [0, 2]].reshape(-1, 3, 2).astype(np.float64)
    a, b, c = roof[:, 0], roof[:, 1], roof[:, 2]
    area = np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])).sum() / 2
    assert area == pytest.approx(polygon.area, rel=1e-3, abs=1e-3)


@SMALL
@given(outlines())
def test_random_outlines_mesh_small(points):
    check_outline(points)


hostile_number = st.one_of(
    coordinate,
    st.just(float("nan")),
    st.just(float("inf")),
    st.just(1e308),
    st.integers(-(10**40), 10**40),
    st.text(max_size=4),
    st.none(),
)
hostile_value = st.recursive(
    st.one_of(hostile_number, st.booleans()),
    lambda inner: st.lists(inner, max_size=5) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=20,
)


@st.composite
def geojson_documents(draw) -> str:
    features = []
    for _ in range(draw(st.integers(0, 4))):
        ring = draw(
            st.one_of(
                st.lists(st.lists(hostile_number, min_size=0, max_size=3), max_size=8),
                st.builds(lambda p: p.tolist() + p[:1].tolist(), outlines()),
                hostile_value,
            )
        )
        geometry = {
            "type": draw(st.sampled_from(["Polygon", "MultiPolygon", "Point", None])),
            "coordinates": draw(st.sampled_from([[ring], [[ring]], ring])),
        }
        properties = draw(
            st.one_of(
                st.dictionaries(
                    st.sampled_from(["height", "building:levels", "levels", "name"]), hostile_value, max_size=3
                ),
                hostile_value,
            )
        )
        features.append({"type": "Feature", "geometry": geometry, "properties": properties})
    return json.dumps({"type": "FeatureCollection", "features": features}, allow_nan=True)


def check_geojson(text: str, folder):
    path = folder / "fuzz.geojson"
    path.write_text(text, encoding="utf-8")
    try:
        map_city(load_map(path))
    except CityshadeError as exc:
        assert "\n" not in str(exc) and str(path) in str(exc), str(exc)


# ------------------------------------------------------------------ the long runs (make fuzz)


@pytest.mark.fuzz
def test_mutated_grammars_long():
    for_a_while(LARGE(given(mutated_grammars())(check_grammar)))


@pytest.mark.fuzz
def test_random_outlines_mesh_long():
    for_a_while(LARGE(given(outlines())(check_outline)))


@pytest.mark.fuzz
def test_hostile_geojson_long(tmp_path_factory):
    folder = tmp_path_factory.mktemp("geojson")
    for_a_while(LARGE(given(geojson_documents())(lambda text: check_geojson(text, folder))))
