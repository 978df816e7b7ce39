"""Every command writes its output whole, and only over a missing or regular file."""

from __future__ import annotations

import gzip
import json
import os
import socket
import stat
from pathlib import Path

import numpy as np
import pytest

from cityshade._files import open_input_stream, output_target, read_input_bytes, write_png
from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.export import check_output
from cityshade.grammar import library_path
from cityshade.render import check_cache_folder

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
    with pytest.raises(UsageError, match="name is too long"):
        output_target(tmp_path / ("n" * 246 + ".png"))
    output_target(tmp_path / ("n" * 200 + ".png"))


def test_output_folders_that_are_files(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("keep")
    assert main(["bench", "relief", "--quick", "--out-dir", str(blocker)]) == 2
    assert "is not a directory" in capsys.readouterr().err
    assert blocker.read_text() == "keep"


def _read_gzip_stream(path: Path, limit: int) -> bytes:
    with open_input_stream(path, limit, limit, compression="gz") as stream:
        return stream.read(limit)


@pytest.mark.parametrize("read", [read_input_bytes, _read_gzip_stream])
@pytest.mark.parametrize("path", ["/dev/zero", "fifo", "dir"])
def test_inputs_must_be_regular_files(tmp_path, path, read):
    if path == "fifo":
        path = tmp_path / "fifo"
        os.mkfifo(path)
    elif path == "dir":
        path = tmp_path
    with pytest.raises(UsageError, match="not a file|is a directory|a character device|a FIFO"):
        read(Path(path), 1024)


def test_compressed_inputs_are_capped_in_all_and_per_line(tmp_path):
    packed = tmp_path / "packed.gz"
    packed.write_bytes(gzip.compress(b"short\n" + b"x" * 5000 + b"\n"))
    with open_input_stream(packed, 10_000, 1000, compression="gz") as stream:
        assert stream.readline() == b"short\n"
        with pytest.raises(UsageError, match="line 2 is longer than the 1000 bytes"):
            stream.readline()
    with open_input_stream(packed, 1000, 10_000, compression="gz") as stream:
        with pytest.raises(UsageError, match="more than the 1000 bytes a file may have .uncompressed."):
            stream.read(4096)


def test_inputs_are_read_up_to_a_cap(tmp_path):
    big = tmp_path / "big"
    big.write_bytes(b"x" * 2000)
    with pytest.raises(UsageError, match="2000 bytes is more than the 1024"):
        read_input_bytes(big, 1024)
    assert read_input_bytes(big, 2000) == b"x" * 2000


# -- folder outputs: a tileset, a tile cache -------------------------------------------------------

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"
FOLDER_COMMANDS = {
    "export 3dtiles": lambda out: ["export", "--map", str(TAGGED), "--format", "3dtiles", "--texel", "1", "--out", out],
    "tile": lambda out: ["tile", str(TAGGED), "--out", out],
    "render --tiles": lambda out: ["render", "--map", str(TAGGED), "--tiles", out, "--out", f"{out}.png"],
}
# what each command's folder held before it carried a marker
LEGACY = {"export 3dtiles": "tileset.json", "tile": "manifest.json", "render --tiles": "manifest.json"}


def _one_line(capsys, argv: list[str]) -> str:
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("command", FOLDER_COMMANDS)
def test_a_folder_without_the_marker_is_never_replaced(command, tmp_path, capsys):
    """An output of an older version, or a folder of the user's that happens to hold its file."""
    folder = tmp_path / "v"
    folder.mkdir()
    (folder / LEGACY[command]).write_text("{}")
    (folder / "THESIS.txt").write_text("keep")
    err = _one_line(capsys, FOLDER_COMMANDS[command](str(folder)))
    assert "has no .cityshade-output file" in err and "delete it yourself" in err
    assert sorted(p.name for p in folder.iterdir()) == sorted([LEGACY[command], "THESIS.txt"])


@pytest.mark.parametrize("command", ["export 3dtiles", "tile"])
def test_an_earlier_output_is_replaced_only_while_it_holds_nothing_else(command, tmp_path, capsys):
    folder = tmp_path / "out"
    argv = FOLDER_COMMANDS[command](str(folder))
    assert main(argv) == 0
    (folder / "tiles" / "notes.txt").write_text("keep")
    assert "holds 'tiles/notes.txt', which cityshade did not write there" in _one_line(capsys, argv)
    assert (folder / "tiles" / "notes.txt").read_text() == "keep"
    (folder / "tiles" / "notes.txt").unlink()
    (folder / "tiles" / "link").symlink_to(tmp_path)  # a link, even to a folder, is not the command's
    assert "holds 'tiles/link'" in _one_line(capsys, argv)
    (folder / "tiles" / "link").unlink()
    assert main(argv) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no temporary folder left


def test_a_marker_of_another_kind_or_format_or_damaged_is_refused(tmp_path, capsys):
    folder = tmp_path / "out"
    assert main(FOLDER_COMMANDS["tile"](str(folder))) == 0
    assert "another kind of cityshade output, not a 3dtiles" in _one_line(
        capsys, FOLDER_COMMANDS["export 3dtiles"](str(folder))
    )
    marker = folder / ".cityshade-output"
    written = json.loads(marker.read_text())
    for content, reason in (
        ({**written, "format": 99}, "written by another cityshade version"),
        ("[" * 100_000, ".cityshade-output' is damaged"),
        ({**written, "files": "tiles"}, ".cityshade-output' is damaged"),
    ):
        marker.write_text(content if isinstance(content, str) else json.dumps(content))
        assert reason in _one_line(capsys, FOLDER_COMMANDS["tile"](str(folder)))
    marker.unlink()
    os.mkfifo(marker)
    assert "a FIFO, not a cityshade output marker" in _one_line(capsys, FOLDER_COMMANDS["tile"](str(folder)))
    assert (folder / "manifest.json").is_file()


@pytest.mark.parametrize("command", FOLDER_COMMANDS)
@pytest.mark.parametrize("where", ["fifo", "long name"])
def test_folder_outputs_follow_the_rules_for_files(command, where, tmp_path, capsys):
    """A FIFO, and a name with no room for the temporary folder's suffix."""
    if where == "fifo":
        os.mkfifo(tmp_path / "fifo")
    out = tmp_path / ("fifo" if where == "fifo" else "n" * 250)
    err = _one_line(capsys, FOLDER_COMMANDS[command](str(out)))
    assert "not a directory (a FIFO)" in err or "name is too long" in err
    assert all(not p.is_dir() for p in tmp_path.iterdir())


@pytest.mark.parametrize("check", [lambda out: check_output(out, "3dtiles"), check_cache_folder])
@pytest.mark.parametrize("where", ["/sys/fs/cgroup/cityshade-test", "/proc/cityshade-test/tiles"])
def test_folder_outputs_under_kernel_file_systems_are_refused(check, where):
    """Paths that do not exist, checked by what each command runs before any work, so that nothing
    is ever written there."""
    with pytest.raises(UsageError, match="kernel file system"):
        check(Path(where))
    assert not Path(where).exists()
