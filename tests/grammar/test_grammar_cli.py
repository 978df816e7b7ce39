"""`cityshade grammar check|render`: exit codes, messages, files written only on success."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.commands import main
from cityshade.grammar import library_path

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FIG12 = str(library_path("fig12.grammar"))


def test_check_valid_file(capsys):
    assert main(["grammar", "check", FIG12]) == 0
    assert "ok, 22 rules" in capsys.readouterr().out


def test_check_reports_location_caret_and_suggestion(tmp_path, capsys):
    bad = tmp_path / "bad.grammar"
    bad.write_text("S->SplitX(Rel, 1, Windw)\nWindow->RepeatX(2, Skip)\nSkip->Skp(0)\n")
    assert main(["grammar", "check", FIG12, str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:1:19: error: undefined rule 'Windw'" in err
    assert "did you mean the rule 'Window'?" in err
    assert f"{bad}:3:7: error: unknown operator 'Skp'" in err and "'Skip'" in err
    assert "^~~~~" in err


def test_render_cpu_writes_colour_and_labels(tmp_path):
    out, labels = tmp_path / "f.png", tmp_path / "l.png"
    assert (
        main(
            [
                "grammar",
                "render",
                FIG12,
                "--cpu",
                "--size",
                "80x64",
                "--seed",
                "2",
                "--out",
                str(out),
                "--labels",
                str(labels),
            ]
        )
        == 0
    )
    assert Image.open(out).size == (80, 64) and Image.open(labels).size == (80, 64)


def test_render_bad_grammar_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.grammar"
    bad.write_bytes(b"\0\1\2")
    out = tmp_path / "f.png"
    assert main(["grammar", "render", str(bad), "--cpu", "--out", str(out)]) == 2
    assert "this is a binary file" in capsys.readouterr().err
    assert not out.exists()


def test_render_on_the_gpu_matches_cpu_and_rule_picks_the_start(tmp_path):
    labels = {}
    for name, extra in (("gpu", []), ("cpu", ["--cpu"]), ("assets", ["--rule", "Assets"])):
        out, label = tmp_path / f"{name}.png", tmp_path / f"{name}_labels.png"
        assert (
            main(
                [
                    "grammar",
                    "render",
                    FIG12,
                    *extra,
                    "--size",
                    "80x64",
                    "--seed",
                    "2",
                    "--out",
                    str(out),
                    "--labels",
                    str(label),
                ]
            )
            == 0
        )
        labels[name] = np.asarray(Image.open(label)).astype(int)
    same = (
        np.all(labels["gpu"] == labels["cpu"], axis=-1) if labels["gpu"].ndim == 3 else labels["gpu"] == labels["cpu"]
    )
    assert same.mean() > 0.999, f"{(~same).sum()} label pixels differ between the GPU and the numpy evaluator"
    assert np.any(labels["assets"] != labels["gpu"]), "--rule Assets drew the same as the start rule"


def test_render_use_and_face_options(tmp_path, capsys):
    grammar = tmp_path / "uses.grammar"
    grammar.write_text(
        "S->Case(building.use == use.office, Glass, Bays)\nBays->RepeatX(1, Pick)\n"
        "Pick->RandUni(0, Brick, Glass)\nGlass->Color(0.2, 0.3, 0.4, window)\nBrick->Color(0.6, 0.3, 0.2)\n"
    )
    labels = {}
    for name, extra in (
        ("front", []),
        ("front_cpu", ["--cpu"]),
        ("side", ["--face", "4"]),
        ("side_cpu", ["--cpu", "--face", "4"]),
        ("office", ["--use", "office"]),
    ):
        out, label = tmp_path / f"{name}.png", tmp_path / f"{name}_labels.png"
        assert (
            main(
                [
                    "grammar",
                    "render",
                    str(grammar),
                    *extra,
                    "--size",
                    "40x16",
                    "--facade",
                    "20x8",
                    "--out",
                    str(out),
                    "--labels",
                    str(label),
                ]
            )
            == 0
        )
        labels[name] = np.asarray(Image.open(label)).astype(int)
    assert (labels["front"] == labels["front_cpu"]).all() and (labels["side"] == labels["side_cpu"]).all()
    assert (labels["front"] != labels["side"]).any()  # another facade of the building: other choices
    assert len(np.unique(labels["office"].reshape(-1, 3), axis=0)) == 1  # an office: all glass
    for bad in (["--use", "store"], ["--face", "2047"], ["--level", "abc"], ["--level=-3"], ["--level", "1.5"]):
        capsys.readouterr()
        assert main(["grammar", "render", str(grammar), *bad, "--out", str(tmp_path / "bad.png")]) == 2
        assert not (tmp_path / "bad.png").exists()
        assert len(capsys.readouterr().err.strip().splitlines()) == 1, bad
