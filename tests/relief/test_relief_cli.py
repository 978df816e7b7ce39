"""`cityshade compress`: compress, --stats, --verify, and clear errors with nothing half-written."""

import numpy as np
import pytest
from PIL import Image

from cityshade.commands import main
from cityshade.relief import generate_facade, save_png_maps


@pytest.fixture()
def pngs(tmp_path):
    save_png_maps(generate_facade(150, 200, texel=0.05), tmp_path / "h.png", tmp_path / "m.png")
    return tmp_path / "h.png", tmp_path / "m.png"


@pytest.mark.parametrize("method", ["svd", "bmf"])
def test_compress_stats_verify(tmp_path, pngs, capsys, method):
    out = tmp_path / "f.cfdm"
    assert (
        main(
            [
                "compress",
                "--height",
                str(pngs[0]),
                "--material",
                str(pngs[1]),
                "--texel",
                "0.05",
                "--method",
                method,
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert main(["compress", "--stats", str(out)]) == 0
    stats = capsys.readouterr().out
    assert "150x200 texels" in stats and f"method {method}" in stats and "boxes" in stats
    assert main(["compress", "--verify", str(out)]) == 0
    assert main(["compress", "--verify", str(out), "--height", str(pngs[0]), "--material", str(pngs[1])]) == 0


def test_verify_reports_a_different_image(tmp_path, pngs, capsys):
    out = tmp_path / "f.cfdm"
    assert main(["compress", "--height", str(pngs[0]), "--material", str(pngs[1]), "--out", str(out)]) == 0
    material = np.array(Image.open(pngs[1]))
    material[5, 5] += 1
    Image.fromarray(material).save(tmp_path / "other.png")
    assert (
        main(["compress", "--verify", str(out), "--height", str(pngs[0]), "--material", str(tmp_path / "other.png")])
        == 1
    )
    assert "material differ from the given images" in capsys.readouterr().err


def test_damaged_files_exit_2(tmp_path, pngs, capsys):
    out = tmp_path / "f.cfdm"
    main(["compress", "--height", str(pngs[0]), "--material", str(pngs[1]), "--out", str(out)])
    data = out.read_bytes()
    (tmp_path / "cut.cfdm").write_bytes(data[: len(data) // 2])
    assert main(["compress", "--verify", str(tmp_path / "cut.cfdm")]) == 2
    assert "cut.cfdm: damaged or truncated" in capsys.readouterr().err
    (tmp_path / "v9.cfdm").write_bytes(data[:8] + (9).to_bytes(4, "little") + data[12:])
    assert main(["compress", "--stats", str(tmp_path / "v9.cfdm")]) == 2
    assert "v9.cfdm: compressed facade format version 9" in capsys.readouterr().err


@pytest.mark.parametrize("option", ["--stats", "--verify"])
def test_a_header_nested_thousands_deep_is_one_line(tmp_path, capsys, option):
    import struct
    import zlib

    from cityshade.relief import VERSION
    from cityshade.relief.testing import _PREFIX, MAGIC

    header = b'{"method": ' + b"[" * 5000 + b"]" * 5000 + b"}"
    body = _PREFIX.pack(MAGIC, VERSION, len(header)) + header
    path = tmp_path / "header_deep_5000.cfdm"
    path.write_bytes(body + struct.pack("<I", zlib.crc32(body)))
    assert main(["compress", option, str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "header_deep_5000.cfdm: malformed compressed facade header (arrays and objects nested more than 64" in err


def test_bad_inputs_write_nothing(tmp_path, pngs, capsys):
    Image.fromarray(np.zeros((20, 20), np.uint16)).save(tmp_path / "small.png")
    out = tmp_path / "never.cfdm"
    assert (
        main(["compress", "--height", str(pngs[0]), "--material", str(tmp_path / "small.png"), "--out", str(out)]) == 2
    )
    assert "must have the same size" in capsys.readouterr().err
    noise = np.random.default_rng(0).integers(0, 60000, (64, 64)).astype(np.uint16)
    Image.fromarray(noise).save(tmp_path / "noise.png")
    assert (
        main(
            [
                "compress",
                "--height",
                str(tmp_path / "noise.png"),
                "--material",
                str(tmp_path / "noise.png"),
                "--max-terms",
                "100",
                "--out",
                str(out),
            ]
        )
        == 2
    )
    assert "noise.png: depth map: the BMF factorisation needs more than 100 terms" in capsys.readouterr().err
    assert (
        main(["compress", "--layout", "F1", "--height", str(pngs[0]), "--material", str(pngs[1]), "--out", str(out)])
        == 2
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.png", "m.png", "noise.png", "small.png"]


def test_compress_a_grammar_file(tmp_path, capsys):
    from cityshade.grammar import library_path

    out = tmp_path / "brick.cfdm"
    assert (
        main(["compress", str(library_path("brick.grammar")), "--facade", "6x8", "--texel", "0.1", "--out", str(out)])
        == 0
    )
    assert main(["compress", "--stats", str(out)]) == 0
    assert "60x80 texels" in capsys.readouterr().out
    assert main(["compress", "--verify", str(out)]) == 0
    bad = tmp_path / "bad.grammar"
    bad.write_text("Facade -> Nonexistent()\n")
    assert main(["compress", str(bad), "--out", str(tmp_path / "x.cfdm")]) == 2
    assert "bad.grammar" in capsys.readouterr().err
    assert not (tmp_path / "x.cfdm").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        ([], "compress needs --out FILE (or --stats FILE / --verify FILE)"),
        (["--out", "x.cfdm"], "give a source: GRAMMAR_FILE, --layout NAME, or --height PNG --material PNG"),
        (["--layout", "F1", "--height", "h.png", "--material", "m.png", "--out", "x.cfdm"], "give one source"),
        (["brick.grammar", "--layout", "F1", "--out", "x.cfdm"], "give one source"),
        (["--height", "h.png", "--out", "x.cfdm"], "--height and --material go together"),
        (["--material", "m.png", "--out", "x.cfdm"], "--height and --material go together"),
        (["--stats", "a.cfdm", "--verify", "a.cfdm"], "--stats and --verify cannot be combined"),
        (["--layout", "F1", "--out", "x.cfdm", "--stats", "a.cfdm"], "--out and --stats cannot be combined"),
        (["--out", "x.cfdm", "--verify", "a.cfdm"], "--out and --verify cannot be combined"),
        (["--stats", "a.cfdm", "--layout", "F1"], "--stats reads only its file; drop --layout"),
        (
            ["--stats", "a.cfdm", "--method", "svd", "--texel", "0.1"],
            "--stats reads only its file; drop --texel, --method",
        ),
        (["--verify", "a.cfdm", "--method", "svd"], "--verify decompresses the file as it was made"),
        (["--verify", "a.cfdm", "--max-terms", "10"], "--verify decompresses the file as it was made"),
        (["--layout", "F1", "--rule", "Facade", "--out", "x.cfdm"], "--rule go with GRAMMAR_FILE"),
        (["--layout", "F1", "--seed", "3", "--out", "x.cfdm"], "--seed go with GRAMMAR_FILE"),
        (
            ["--height", "h.png", "--material", "m.png", "--facade", "6x8", "--out", "x.cfdm"],
            "--facade sizes a GRAMMAR_FILE or --layout facade",
        ),
        (
            ["--layout", "F1", "--depth-unit", "0.02", "--out", "x.cfdm"],
            "--depth-unit goes with --height and --material",
        ),
    ],
)
def test_bad_combinations_are_one_line_and_exit_2(tmp_path, monkeypatch, capsys, args, message):
    """Each option belongs to one use of the command: one that would do nothing is refused, before
    anything is read or written."""
    monkeypatch.chdir(tmp_path)
    assert main(["compress", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("cityshade: error: ") and message in err[0], err
    assert list(tmp_path.iterdir()) == []


def test_verify_against_a_layout_and_a_grammar_seed(tmp_path, capsys):
    """The good combinations: --verify with a source compares with it; --seed with GRAMMAR_FILE."""
    from cityshade.grammar import library_path

    out = tmp_path / "f1.cfdm"
    assert main(["compress", "--layout", "F1", "--facade", "2x3", "--texel", "0.1", "--out", str(out)]) == 0
    assert main(["compress", "--verify", str(out), "--layout", "F1", "--facade", "2x3", "--texel", "0.1"]) == 0
    assert "decompress exactly to the given images" in capsys.readouterr().out
    assert main(["compress", "--verify", str(out), "--layout", "F3", "--facade", "2x3", "--texel", "0.1"]) == 1
    seeded = tmp_path / "seeded.cfdm"
    assert (
        main(
            [
                "compress",
                str(library_path("brick.grammar")),
                "--seed",
                "5",
                "--facade",
                "4x4",
                "--texel",
                "0.2",
                "--out",
                str(seeded),
            ]
        )
        == 0
    )
