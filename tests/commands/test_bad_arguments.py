"""Bad arguments and numbers: one line, exit code 2, no file, and the same error from the Python API."""

from __future__ import annotations

import pytest

import cityshade
from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.grammar import GrammarError, library_path, loads

FIG12 = str(library_path("fig12.grammar"))


@pytest.mark.parametrize(
    "args, message",
    [
        (["render", "--seed", "-1"], "invalid --seed '-1'; a seed is a whole number from 0 to 2147483647"),
        (["render", "--seed", "2147483648"], "invalid --seed '2147483648'"),
        (["render", "--seed", "1e3"], "invalid --seed '1e3'"),
        (["render", "--samples", "3"], "argument --samples: invalid choice: 3"),
        (["render", "--seed", "x"], "invalid --seed 'x'"),
        (["render", "--footprints", "missing.geojson"], "missing.geojson: cannot read the map"),
        (["view", "--camera", "nowhere"], "unknown camera 'nowhere'"),
        (["render", "--bogus"], "unrecognized arguments: --bogus"),
        (["bench"], "the following arguments are required: name"),
        (["teleport"], "invalid choice: 'teleport'"),
        (["grammar", "render", FIG12, "--size", "0x0"], "invalid size '0x0'"),
        (["grammar", "render", FIG12, "--size", "99999999999x2"], "invalid size '99999999999x2'"),
        (["grammar", "render", FIG12, "--facade", "0x5"], "invalid --facade '0x5'"),
        (["grammar", "render", FIG12, "--facade", "nanx5"], "invalid --facade 'nanx5'"),
        (["grammar", "render", FIG12, "--seed", "4294967296"], "invalid --seed '4294967296'"),
        (["grammar", "render", FIG12, "--rule", "Nowhere", "--cpu"], "no rule named 'Nowhere'"),
        (["grammar", "render", FIG12, "--rule", "Nope"], "no rule named 'Nope'"),
        (["compress", "--layout", "F1", "--texel", "nan"], "invalid --texel nan"),
        (["compress", "--layout", "F1", "--texel", "inf"], "invalid --texel inf"),
        (["compress", "--layout", "F1", "--depth-unit", "-1"], "invalid --depth-unit -1"),
        (["compress", "--layout", "F1", "--max-terms", "-3"], "invalid --max-terms -3"),
        (["compress", "--layout", "F1", "--seed", "-5"], "invalid --seed '-5'"),
        (["video", "--size", "8x8"], "give a name ending in .mp4"),
    ],
)
def test_bad_arguments_are_one_line_and_exit_2(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.chdir(tmp_path)
    out = (
        ["--out", "video" if args[0] == "video" else "out.file"] if args[0] in ("grammar", "compress", "video") else []
    )
    assert main(args + out) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], captured.err
    assert lines[0].startswith("cityshade: error: ") and "Traceback" not in captured.err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"lights": 2}, "invalid --lights 2; the share of lit rooms is a number from 0 to 1"),
        ({"lights": float("nan")}, "invalid --lights nan"),
        ({"size": (0, 0)}, "invalid size (0, 0)"),
        ({"size": (640.5, 360)}, "invalid size (640.5, 360)"),
        ({"size": "big"}, "invalid size 'big'"),
        ({"seed": -1}, "invalid --seed -1"),
        ({"seed": 2**40}, "invalid --seed 1099511627776"),
        ({"samples": 3}, "invalid --samples 3"),
        ({"colour": "red"}, "unknown render setting 'colour'"),
    ],
)
def test_the_api_raises_the_cli_error(kwargs, message):
    with pytest.raises(UsageError) as info:
        cityshade.render_image("default", **kwargs)
    assert message in str(info.value) and info.value.exit_code == 2


@pytest.mark.parametrize(
    "text, message",
    [
        ("S->RepeatX(1e999, A)", "1e999 does not fit the GPU's 16-bit numbers"),
        ("S->RepeatX(70000, A)", "70000 does not fit the GPU's 16-bit numbers"),
        ("S->Skip(99999999999999999999999)", "does not fit the GPU's 16-bit numbers"),
        ("S->RepeatX(1e-30, A)", "size must be > 0, got 1e-30"),
        ("S->SplitX(Rel, 60000, A, Rel, 60000, A)", "the relative sizes add up to 120000"),
        ("S->SplitY(Abs, 40000, A, Abs, 40000, A)", "the absolute sizes add up to 80000"),
    ],
)
def test_grammar_numbers_beyond_half_floats_are_refused_with_a_location(text, message):
    with pytest.raises(GrammarError) as info:
        loads(text + "\nA->Mat(Color, Rep:wall1, 0, 0, 1, 1)\n")
    first = str(info.value).splitlines()[0]
    assert first.startswith("<string>:1:") and message in first


def test_the_api_checks_frames():
    with pytest.raises(UsageError, match="invalid frames -1"):
        cityshade.render_city("default", frames=-1)


@pytest.mark.parametrize("json_path", ["/proc/cityshade-bench.json", "blocker/trees.json"])
def test_bench_json_that_cannot_be_written_fails_before_measuring(tmp_path, monkeypatch, capsys, json_path):
    import cityshade.bench.trees

    def measure(**_):
        raise AssertionError("the benchmark ran although its JSON cannot be written")

    monkeypatch.chdir(tmp_path)
    (tmp_path / "blocker").write_text("a file, not a folder")
    monkeypatch.setattr(cityshade.bench.trees, "run", measure)
    assert main(["bench", "trees", "--quick", "--json", json_path]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("cityshade: error: cannot write") and json_path in lines[0], lines
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]
