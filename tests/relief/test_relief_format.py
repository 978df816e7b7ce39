"""The .cfdm file: exact round trip, checksum, version, truncation; PNG map loading errors."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from cityshade.errors import CityshadeError
from cityshade.relief import (
    MAP_NAMES,
    VERSION,
    DetailMaps,
    compress,
    detail_matrices,
    from_bytes,
    generate_facade,
    load_png_maps,
    read_compressed,
    save_png_maps,
    to_bytes,
    write_compressed,
)
from cityshade.relief.testing import MAGIC
from relief_strategies import piecewise_constant


@pytest.fixture(scope="module")
def maps():
    return generate_facade(160, 240, texel=0.05)


@pytest.mark.parametrize("method", ["svd", "bmf"])
def test_file_round_trip_is_exact(tmp_path, maps, method):
    facade = compress(maps, method)
    path = tmp_path / "f.cfdm"
    write_compressed(path, facade)
    back = read_compressed(path)
    assert [p.name for p in tmp_path.iterdir()] == ["f.cfdm"], "no temporary file left behind"
    matrices, boxes = detail_matrices(maps)
    out = back.decompress()
    for name in MAP_NAMES:
        assert np.array_equal(out[name], matrices[name]), name
        assert back.factors[name].terms == facade.factors[name].terms
    assert np.array_equal(back.boxes, boxes)
    assert back.digests == facade.digests and back.texel == maps.texel


def test_damage_is_detected(maps):
    data = bytearray(to_bytes(compress(maps, "bmf")))
    with pytest.raises(CityshadeError, match="truncated|checksum"):
        from_bytes(bytes(data[:-100]), "f.cfdm")
    with pytest.raises(CityshadeError, match="truncated"):
        from_bytes(bytes(data[:10]), "f.cfdm")
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 0x10
    with pytest.raises(CityshadeError, match="f.cfdm: damaged"):
        from_bytes(bytes(flipped), "f.cfdm")
    newer = bytearray(data)
    newer[8:12] = (VERSION + 1).to_bytes(4, "little")
    with pytest.raises(CityshadeError, match=f"version {VERSION + 1}"):
        from_bytes(bytes(newer), "f.cfdm")
    with pytest.raises(CityshadeError, match="not a compressed facade"):
        from_bytes(b"PK\x03\x04" + bytes(data[4:]), "f.cfdm")
    assert bytes(data[:8]) == MAGIC


def test_png_pair_round_trip(tmp_path, maps):
    save_png_maps(maps, tmp_path / "h.png", tmp_path / "m.png")
    back = load_png_maps(tmp_path / "h.png", tmp_path / "m.png", maps.texel, maps.depth_unit)
    assert np.array_equal(back.depth, maps.depth) and np.array_equal(back.material, maps.material)


def test_png_errors_name_the_file(tmp_path, maps):
    save_png_maps(maps, tmp_path / "h.png", tmp_path / "m.png")
    Image.fromarray(np.zeros((10, 10), np.uint8)).save(tmp_path / "small.png")
    Image.fromarray(np.zeros((240, 160, 3), np.uint8)).save(tmp_path / "rgb.png")
    Image.fromarray(np.zeros((240, 160), np.float32)).save(tmp_path / "float.tiff")
    with pytest.raises(CityshadeError, match="small.png is 10x10.*same size"):
        load_png_maps(tmp_path / "h.png", tmp_path / "small.png", 0.05, 0.01)
    with pytest.raises(CityshadeError, match="rgb.png: the material image has mode RGB"):
        load_png_maps(tmp_path / "h.png", tmp_path / "rgb.png", 0.05, 0.01)
    with pytest.raises(CityshadeError, match="float.tiff: the material image has mode F"):
        load_png_maps(tmp_path / "h.png", tmp_path / "float.tiff", 0.05, 0.01)
    with pytest.raises(CityshadeError, match="missing.png: no such file"):
        load_png_maps(tmp_path / "missing.png", tmp_path / "m.png", 0.05, 0.01)


@settings(max_examples=25, deadline=None)
@given(piecewise_constant(max_side=24, max_value=60), st.sampled_from(["svd", "bmf"]))
def test_random_maps_survive_the_file(depth, method):
    maps = DetailMaps(depth, (depth % 5).astype(np.uint16), 0.1, 0.01)
    facade = compress(maps, method)
    back = from_bytes(to_bytes(facade))
    matrices, boxes = detail_matrices(maps)
    for name, matrix in back.decompress().items():
        assert np.array_equal(matrix, matrices[name]), name
    assert np.array_equal(back.boxes, boxes)
