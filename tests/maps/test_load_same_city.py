"""A change to the load that is meant to be faster, not different, builds the same city: the
vertices and building records of `scene.batch`, every layer's ground, lights and trees, and every
viewpoint, compared byte for byte with stored digests (tests/data/load-digests.json). The built-in
district, Helsinki, and Helsinki tiled to 10,000 buildings (slow). The digests are made again, with
`python tests/maps/test_load_same_city.py HELSINKI_PBF TILED_PBF`, by a change that means to alter
the city; bytes depend on numpy, shapely and GEOS, so under other versions than the digests' the
comparison is skipped with the versions named."""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import load_map, map_city, tiled_extract
from cityshade.scene import batch, make_city

DIGESTS = Path(__file__).parents[1] / "data" / "load-digests.json"
TILED_BUILDINGS = 10_000


def _digest(array: np.ndarray) -> str:
    array = np.ascontiguousarray(array)
    return hashlib.sha256(f"{array.dtype}{array.shape}".encode() + array.tobytes()).hexdigest()


def city_digests(city) -> dict[str, str]:
    """A digest of each array the load built, and each viewpoint as written out in full."""
    vertices, records = batch(city.masses)
    out = {"vertices": _digest(vertices), "records": _digest(records)}
    for layer in city.layers:
        out[f"layer {layer.name} ground"] = _digest(layer.ground)
        out[f"layer {layer.name} lights"] = _digest(layer.lights)
        if layer.trees is not None:
            out[f"layer {layer.name} trees"] = _digest(layer.trees)
    out.update({f"camera {name}": repr(camera) for name, camera in city.viewpoints.items()})
    return out


def _assert_same(name: str, city) -> None:
    stored = json.loads(DIGESTS.read_text())
    if stored["made with"] != _versions():
        pytest.skip(f"digests made with {stored['made with']}; this run has {_versions()}")
    expected, made = stored[name], city_digests(city)
    differing = sorted(key for key in expected.keys() | made.keys() if expected.get(key) != made.get(key))
    assert not differing, (
        f"{name}: {len(differing)} of {len(expected)} parts differ from the stored city: {differing} "
        f"(digests made with {stored['made with']}; this run: {_versions()})"
    )


def _versions() -> str:
    return f"numpy {np.__version__}, shapely {shapely.__version__}, GEOS {shapely.geos_version_string}"


def test_the_district_is_the_same_city():
    _assert_same("district", make_city("default"))


def test_helsinki_is_the_same_city(helsinki_pbf):
    _assert_same("Helsinki", map_city(load_map(helsinki_pbf)))


@pytest.mark.slow
def test_tiled_helsinki_is_the_same_city(helsinki_pbf, tmp_path):
    extract = tmp_path / "tiled.osm.pbf"
    tiled_extract(helsinki_pbf, extract, TILED_BUILDINGS)
    _assert_same("tiled Helsinki", map_city(load_map(extract)))


if __name__ == "__main__":  # write the digests of the tree on sys.path: python THIS HELSINKI_PBF TILED_PBF
    helsinki, tiled = sys.argv[1:3]
    digests = {
        "made with": _versions(),
        "district": city_digests(make_city("default")),
        "Helsinki": city_digests(map_city(load_map(helsinki))),
        "tiled Helsinki": city_digests(map_city(load_map(tiled))),
    }
    DIGESTS.write_text(json.dumps(digests, indent=1) + "\n")
