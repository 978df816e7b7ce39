"""Sizes that would exhaust memory or exceed the GPU's limits are refused up front, naming the
largest size that fits; large CPU facade renders run in tiles."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

import cityshade._budget as budget
from cityshade._budget import check_gl_size
from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.grammar import compile_grammars, library_path, load

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FIG12 = str(library_path("fig12.grammar"))


@pytest.fixture
def one_gib(monkeypatch):
    monkeypatch.setattr(budget, "available_memory", lambda: 2 * 2**30)  # 1 GiB may be used


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_a_render_larger_than_memory_names_the_size_that_fits(tmp_path, one_gib, capsys):
    from cityshade.render.testing import frame_bytes_per_pixel

    out = tmp_path / "city.png"
    assert main(["render", "--size", "16384x12288", "--out", str(out)]) == 2
    line = _one_line(capsys)
    per_pixel = frame_bytes_per_pixel(4)
    need = 16384 * 12288 * per_pixel / 2**30
    fits = budget.largest_fitting((16384, 12288), 2**30 / per_pixel)
    assert f"a render at 16384x12288 needs about {need:.1f} GiB" in line
    assert (
        line.endswith(f"the largest --size that fits is {fits[0]}x{fits[1]}") and fits[0] * fits[1] * per_pixel <= 2**30
    )
    assert fits[0] / fits[1] == pytest.approx(4 / 3, rel=1e-3) and not out.exists()


def test_the_cpu_grammar_render_is_checked_against_memory(tmp_path, one_gib, capsys):
    assert main(["grammar", "render", FIG12, "--cpu", "--size", "4096x4096", "--out", str(tmp_path / "f.png")]) == 2
    assert "grammar render --cpu at 4096x4096 needs about 2.3 GiB" in _one_line(capsys)


def test_the_cpu_grammar_render_in_tiles_equals_one_piece(monkeypatch):
    import cityshade.grammar._reference as reference
    from cityshade.assets import tile_array
    from cityshade.grammar import seed_vector

    compiled = compile_grammars({"g": load(FIG12)})
    args = (compiled, compiled.address("g", None), (20.0, 16.0), (61, 47), seed_vector(3), tile_array(128))
    whole = reference.evaluate_facade(*args)
    monkeypatch.setattr(reference, "CHUNK_PIXELS", 500)
    tiled = reference.evaluate_facade(*args)
    for name, value in vars(whole).items():
        assert np.array_equal(value, vars(tiled)[name]), name


class _Context:
    info = {"GL_MAX_TEXTURE_SIZE": 8192, "GL_MAX_RENDERBUFFER_SIZE": 4096, "GL_MAX_VIEWPORT_DIMS": (16384, 16384)}


def test_targets_beyond_the_gl_limits_are_refused():
    with pytest.raises(
        UsageError,
        match=r"larger than this OpenGL allows \(4096 pixels a side\); the largest "
        r"--size that fits is 4096x2048",
    ):
        check_gl_size(_Context(), (8000, 4000))
    check_gl_size(_Context(), (4096, 4096))


@pytest.mark.parametrize(
    "args",
    [
        ["--layout", "F1", "--facade", "1000x1000"],
        [FIG12, "--facade", "1000x1000"],
        [FIG12, "--facade", "100x100", "--texel", "0.001"],
    ],
)
def test_compress_facades_beyond_the_texel_limit(tmp_path, args, capsys):
    assert main(["compress", *args, "--out", str(tmp_path / "f.cfdm")]) == 2
    line = _one_line(capsys)
    assert "a facade may have at most 16384 texels a side and 16777216 texels in all" in line
    assert not list(tmp_path.iterdir())


def _png_declaring(width: int, height: int) -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"")) + chunk(b"IEND", b"")


@pytest.mark.parametrize("width", [12000, 20000])  # under and over Pillow's own bomb limit
def test_a_tiny_png_declaring_megapixels_is_not_decoded(tmp_path, width, capsys):
    bomb = tmp_path / "bomb.png"
    bomb.write_bytes(_png_declaring(width, 9000))
    assert len(bomb.read_bytes()) < 100
    assert main(["compress", "--height", str(bomb), "--material", str(bomb), "--out", str(tmp_path / "f.cfdm")]) == 2
    line = _one_line(capsys)
    assert f"bomb.png: the height image is {width}x9000 texels" in line or "decompression bomb" in line
