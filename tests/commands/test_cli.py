"""The render command: pictures for good input, one-line errors and no file for bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def run_cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "cityshade", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )


@pytest.mark.parametrize(
    "args, message",
    [
        (["--camera", "nowhere"], "unknown camera 'nowhere'; allowed: street"),
        (["--city", "atlantis"], "unknown city 'atlantis'; allowed: default, grid"),
        (["--size", "0x0"], "invalid size '0x0'"),
        (["--size", "abcx10"], "invalid size 'abcx10'"),
        (["--lights", "1.5"], "invalid --lights '1.5'"),
        (["--time", "25:00"], "invalid time '25:00'"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_no_file(tmp_path, args, message):
    out = tmp_path / "city.png"
    result = run_cli(
        "render",
        *args,
        "--size" if "--size" not in args else "--out",
        *(["64x36"] if "--size" not in args else []),
        *(["--out", str(out)] if "--size" not in args else [str(out)]),
    )
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists() and not list(tmp_path.iterdir())


def test_output_under_a_file_cannot_be_written(tmp_path):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("not a folder")
    result = run_cli("render", "--size", "64x36", "--out", str(blocker / "city.png"))
    assert result.returncode == 2 and "cannot write" in result.stderr and "is not a directory" in result.stderr
    assert blocker.read_text() == "not a folder"


def test_output_path_that_is_a_directory(tmp_path):
    result = run_cli("render", "--size", "64x36", "--out", str(tmp_path))
    assert result.returncode == 2 and "is a directory" in result.stderr


def test_render_writes_png_and_reports_frame(tmp_path):
    out = tmp_path / "sub" / "city.png"
    result = run_cli("render", "--size", "96x54", "--camera", "aerial", "--lights", "0.5", "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert out.exists() and "ms (median of 3) on " in result.stdout and "4x MSAA" in result.stdout
    from PIL import Image

    assert Image.open(out).size == (96, 54)


def test_warnings_are_one_line_each(tmp_path):
    """cityshade's own warnings (here faces too narrow for their grammar) reach stderr as one line
    each, `cityshade: warning: ...`, without the Python source line behind them."""
    data = Path(__file__).parents[1] / "data" / "maps" / "shed.osm"
    result = run_cli("tile", str(data), "--out", str(tmp_path / "tiles"))
    assert result.returncode == 0, result.stderr
    lines = result.stderr.strip().splitlines()
    print(lines)
    warned = [line for line in lines if line.startswith("cityshade: warning: ")]
    assert any("narrower than their building's grammar" in line for line in warned)
    assert not any("Warning:" in line or line.startswith(" ") for line in lines)
