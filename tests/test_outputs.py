"""Every command writes its output whole, and only over a missing or regular file."""

from __future__ import annotations

import os
import socket
import stat
from pathlib import Path

import numpy as np
import pytest

from cityshade._files import output_target, read_input_bytes, write_png
from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.grammar import library_path

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FIG12 = str(library_path("fig12.grammar"))


def _commands(out: Path) -> dict[str, list[str]]:
    return {
        "grammar render": ["grammar", "render", FIG12, "--cpu", "--size", "16x16", "--out", str(out)],
        "grammar labels": [
            "grammar",
            "render",
            FIG12,
            "--cpu",
            "--size",
            "16x16",
            "--out",
            str(out.parent / "ok.png"),
            "--labels",
            str(out),
        ],
        "compress": ["compress", "--layout", "F1", "--facade", "1x1", "--texel", "0.1", "--out", str(out)],
        "render": ["render", "--size", "8x8", "--out", str(out)],
        "video": ["video", "--size", "8x8", "--frames", "1", "--out", str(out)],
        "bench json": ["bench", "relief", "--quick", "--json", str(out)],
    }


def _special(kind: str, tmp_path: Path) -> Path:
    path = tmp_path / f"special-{kind}"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "socket":
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(path))
        server.close()
    elif kind == "directory":
        path.mkdir()
    elif kind == "device link":
        path.symlink_to("/dev/null")
    return path


@pytest.mark.parametrize("kind", ["fifo", "socket", "directory", "device link"])
@pytest.mark.parametrize("command", ["grammar render", "grammar labels", "compress", "render", "video", "bench json"])
def test_special_outputs_are_refused_with_one_line(tmp_path, kind, command, capsys):
    path = _special(kind, tmp_path)
    before = os.lstat(path)
    assert main(_commands(path)[command]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0], err
    after = os.lstat(path)
    assert stat.S_IFMT(after.st_mode) == stat.S_IFMT(before.st_mode) and after.st_ino == before.st_ino
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


@pytest.mark.parametrize("path", ["/dev/null", "/dev/zero", "/proc/self/comm", "/sys/kernel/x.png", "/proc/new.png"])
def test_devices_and_kernel_file_systems_are_refused(path):
    with pytest.raises(UsageError, match="kernel file system|character device"):
        output_target(Path(path))


def test_a_link_to_a_regular_file_is_followed_and_kept(tmp_path):
    target = tmp_path / "real.png"
    target.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(target)
    write_png(np.zeros((2, 3, 3), np.uint8), link)
    assert link.is_symlink() and target.read_bytes().startswith(b"\x89PNG")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.png", "real.png"]


def test_a_name_too_long_once_the_temporary_suffix_is_added(tmp_path):
    with pytest.raises(UsageError, match="file name is too long"):
        output_target(tmp_path / ("n" * 246 + ".png"))
    output_target(tmp_path / ("n" * 200 + ".png"))


def test_output_folders_that_are_files(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("keep")
    assert main(["bench", "relief", "--quick", "--out-dir", str(blocker)]) == 2
    assert "is not a directory" in capsys.readouterr().err
    assert blocker.read_text() == "keep"


@pytest.mark.parametrize("path", ["/dev/zero", "fifo", "dir"])
def test_inputs_must_be_regular_files(tmp_path, path):
    if path == "fifo":
        path = tmp_path / "fifo"
        os.mkfifo(path)
    elif path == "dir":
        path = tmp_path
    with pytest.raises(UsageError, match="not a file|is a directory|a character device|a FIFO"):
        read_input_bytes(Path(path), 1024)


def test_inputs_are_read_up_to_a_cap(tmp_path):
    big = tmp_path / "big"
    big.write_bytes(b"x" * 2000)
    with pytest.raises(UsageError, match="2000 bytes is more than the 1024"):
        read_input_bytes(big, 1024)
    assert read_input_bytes(big, 2000) == b"x" * 2000
