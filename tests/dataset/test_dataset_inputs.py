"""cityshade dataset against hostile and careless inputs, without starting Ray: dataset folders
whose manifest names files outside them, damaged manifests, records and sample files, configs
that are endless, deep or not finite, counts past their caps and addresses where no Ray cluster
answers. Each is one line and exit code 2, reads nothing outside the folder and writes nothing."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from cityshade.commands import main
from cityshade.dataset import load_config, parse_config, read_manifest, write_preview, write_shards
from cityshade.errors import UsageError
from dataset_folders import make_folder, opened_files, record, row, write_rows

SECRET = b"cityshade-test-secret\n" * 360  # 7920 bytes: neither its text nor its size may show
RESUME = ["dataset", "--city", "default", "--samples", "2", "--resume"]


@pytest.fixture
def outside(tmp_path) -> Path:
    """A file beside the dataset folder, which nothing may read."""
    path = tmp_path / "secret.txt"
    path.write_bytes(SECRET)
    return path


@pytest.fixture
def folder(tmp_path) -> Path:
    make_folder(tmp_path / "ds")
    return tmp_path / "ds"


def _run(capsys, argv) -> tuple[int, str]:
    code = main([str(a) for a in argv])
    return code, capsys.readouterr().err


def _one_line(err: str, *words: str):
    assert err.startswith("cityshade: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err and "cityshade-test-secret" not in err and "7920" not in err, err
    for word in words:
        assert word in err, (word, err)


def _snapshot(path: Path) -> dict:
    return {p: (p.read_bytes() if p.is_file() else None) for p in sorted(path.rglob("*"))}


# --- 1. paths in the manifest are confined to the folder ------------------------------------------


def _hostile(folder: Path, outside: Path, how: str, column: str):
    rows = read_manifest(folder)
    if how == "symlink":  # the sample's own file made a link out of the folder
        (folder / rows[0][column]).unlink()
        (folder / rows[0][column]).symlink_to(outside)
        return
    if how == "symlinked folder":  # samples/ itself a link to a folder outside holding the same files
        copy = outside.parent / "elsewhere"
        (folder / "samples").rename(copy)
        (folder / "samples").symlink_to(copy)
        (copy / Path(rows[0][column]).name).write_bytes(SECRET)
        return
    rows[0][column] = {
        "absolute": str(outside),
        "/etc/passwd": "/etc/passwd",
        "/proc/self/environ": "/proc/self/environ",
        "..": "../secret.txt",
        "deep ..": "../../../../../../etc/passwd",
        "samples/..": "samples/../../secret.txt",
    }[how]
    write_rows(folder, rows)


HOW = ["absolute", "/etc/passwd", "/proc/self/environ", "..", "deep ..", "samples/..", "symlink", "symlinked folder"]


@pytest.mark.parametrize("how", HOW)
@pytest.mark.parametrize("column", ["rgb", "meta"])
def test_resume_and_shards_read_nothing_outside_the_folder(folder, outside, capsys, how, column):
    _hostile(folder, outside, how, column)
    before = _snapshot(folder)
    with opened_files() as seen:
        code, err = _run(capsys, [*RESUME, "--out", folder, "--shards", "1"])
    assert code == 2
    first = "rgb" if how == "symlinked folder" else column  # every file of the sample leaves the folder
    _one_line(err, f"{folder / 'manifest.parquet'}: row of sample 0, column {first}: ", "only files inside")
    assert not {str(outside), "/etc/passwd", "/proc/self/environ"} & seen
    assert not any(str(p).startswith(str(outside.parent / "elsewhere")) for p in seen)
    assert _snapshot(folder) == before and not (folder / "shards").exists()


@pytest.mark.parametrize("how", HOW)
def test_preview_reads_nothing_outside_the_folder(folder, outside, capsys, how):
    _hostile(folder, outside, how, "rgb")
    with opened_files() as seen:
        code, err = _run(capsys, ["dataset", "--preview", folder])
    assert code == 2
    _one_line(err, "row of sample 0, column rgb: ")
    assert not {str(outside), "/etc/passwd", "/proc/self/environ"} & seen
    assert not (folder / "preview.png").exists()


def test_shards_of_a_sound_folder_still_hold_every_file(folder, capsys):
    code, err = _run(capsys, [*RESUME, "--out", folder, "--shards", "1"])
    assert code == 0, err
    import tarfile

    with tarfile.open(folder / "shards" / "000001.tar") as tar:
        assert sorted(tar.getnames()) == sorted(Path(p).name for p in row(1).values() if str(p).startswith("samples/"))


@pytest.mark.parametrize("name", ["preview.png", "shards", "manifest.parquet", "dataset.json"])
def test_outputs_are_not_written_through_links_out_of_the_folder(folder, outside, capsys, name):
    target = outside if name != "shards" else outside.parent
    if name in ("manifest.parquet", "dataset.json"):
        (folder / name).unlink()
    (folder / name).symlink_to(target)
    argv = ["dataset", "--preview", folder] if name == "preview.png" else [*RESUME, "--out", folder, "--shards", "1"]
    code, err = _run(capsys, argv)
    assert code == 2
    _one_line(err, f"{folder / name}: the path passes a symbolic link leading out of {folder}")
    assert outside.read_bytes() == SECRET and sorted(p.name for p in outside.parent.iterdir()) == ["ds", "secret.txt"]


# --- 9. damaged folders are one line naming the file ----------------------------------------------


def _damage(folder: Path, how: str):
    manifest = folder / "manifest.parquet"
    data = manifest.read_bytes()
    table = pq.read_table(manifest)
    if how == "empty":
        manifest.write_bytes(b"")
    elif how == "truncated":
        manifest.write_bytes(data[: len(data) // 2])
    elif how == "footer cut":
        manifest.write_bytes(data[:-3])
    elif how == "not parquet":
        manifest.write_bytes(b"index,rgb\n0,x\n")
    elif how == "index of strings":
        pq.write_table(table.set_column(0, "index", pa.array(["0", "1"])), manifest)
    elif how == "index of floats":
        pq.write_table(table.set_column(0, "index", pa.array([0.0, 1.5])), manifest)
    elif how == "missing column":
        pq.write_table(table.drop_columns(["rgb"]), manifest)
    elif how == "path of numbers":
        pq.write_table(table.set_column(table.schema.get_field_index("depth"), "depth", pa.array([1, 2])), manifest)
    elif how == "null path":
        pq.write_table(table.set_column(table.schema.get_field_index("meta"), "meta", pa.array([None, "x"])), manifest)
    elif how == "repeated index":
        pq.write_table(table.set_column(0, "index", pa.array([1, 1])), manifest)
    elif how == "negative index":
        pq.write_table(table.set_column(0, "index", pa.array([-1, 1])), manifest)
    elif how == "fifo":
        manifest.unlink()
        os.mkfifo(manifest)
    elif how == "directory":
        manifest.unlink()
        manifest.mkdir()
    else:
        raise AssertionError(how)


DAMAGE = [
    "empty",
    "truncated",
    "footer cut",
    "not parquet",
    "index of strings",
    "index of floats",
    "missing column",
    "path of numbers",
    "null path",
    "repeated index",
    "negative index",
    "fifo",
    "directory",
]


@pytest.mark.parametrize("how", DAMAGE)
@pytest.mark.parametrize("command", ["resume", "preview"])
def test_a_damaged_manifest_is_one_line(folder, capsys, how, command):
    _damage(folder, how)
    argv = [*RESUME, "--out", folder] if command == "resume" else ["dataset", "--preview", folder]
    before = _snapshot(folder)
    code, err = _run(capsys, argv)
    assert code == 2
    _one_line(err, str(folder / "manifest.parquet"))
    assert _snapshot(folder) == before, "a damaged dataset folder was changed"


@pytest.mark.parametrize(
    "column, content, words",
    [
        ("rgb", b"not an image at all", "column rgb: not a readable PNG image"),
        ("class", b"\x89PNG\r\n\x1a\n truncated", "column class: not a readable PNG image"),
        ("depth", b"PK\x03\x04 garbage", "column depth: not a readable .npz archive"),
        ("instance", None, "column instance: a float32 array"),
        ("depth", b"", "column depth: not a readable .npz archive"),
    ],
)
def test_a_damaged_sample_file_is_one_line_in_preview(folder, capsys, column, content, words):
    path = folder / row(0)[column]
    if content is None:  # a depth map where the instances belong
        content = (folder / row(0)["depth"]).read_bytes()
    path.write_bytes(content)
    code, err = _run(capsys, ["dataset", "--preview", folder])
    assert code == 2
    _one_line(err, f"{folder / 'manifest.parquet'}: row of sample 0, {words}", "--resume")


def test_a_missing_or_special_sample_file_is_one_line_in_shards(folder, capsys):
    (folder / row(1)["normal"]).unlink()
    os.mkfifo(folder / row(1)["normal"])
    code, err = _run(capsys, ["dataset", "--preview", folder])  # the preview does not read normals
    assert code == 0, err
    assert write_preview(folder) == folder / "preview.png"
    with pytest.raises(UsageError, match="row of sample 1, column normal: this is a FIFO"):
        write_shards(folder, 1)


@pytest.mark.parametrize(
    "content, words",
    [
        ("[" * 100_000 + "]" * 100_000, "nested more than 64 levels deep"),
        ('{"a": ' * 100_000 + "1" + "}" * 100_000, "nested more than 64 levels deep"),
        ("[1, 2]", "not a JSON object"),
        ('{"seed": ', "not JSON"),
        (b"\xff\xfe{}", "not UTF-8"),
        ("fifo", "this is a FIFO"),
    ],
)
def test_a_damaged_record_is_one_line(folder, capsys, content, words):
    record = folder / "dataset.json"
    record.unlink()
    if content == "fifo":
        os.mkfifo(record)
    else:
        record.write_bytes(content if isinstance(content, bytes) else content.encode())
    code, err = _run(capsys, [*RESUME, "--out", folder])
    assert code == 2
    _one_line(err, str(record), words)


def test_a_hostile_record_is_shown_short(folder, capsys):
    hostile = {**record(), "seed": "x" * 100_000, "\nweird key": [[[[[["x" * 1000]]]]]]}  # sorts first
    (folder / "dataset.json").write_text(json.dumps(hostile))
    code, err = _run(capsys, [*RESUME, "--out", folder])
    assert code == 2 and len(err) < 400
    _one_line(err, "--resume: ", "was made with")


# --- 4. configs: capped regular files, bounded nesting, finite numbers ----------------------------


def _config_fails(tmp_path, capsys, config: Path, *words):
    out = tmp_path / "new"
    code, err = _run(capsys, ["dataset", "--city", "default", "--samples", "2", "--out", out, "--config", config])
    assert code == 2
    _one_line(err, *words)
    assert not out.exists()


@pytest.mark.parametrize(
    "text, words",
    [
        ("[image]\nfov = " + "[" * 100_000 + "]" * 100_000 + "\n", "nested more than 64 levels deep"),
        ("x = " + "{a = " * 100_000 + "1" + "}" * 100_000 + "\n", "nested more than 64 levels deep"),
        ("[image" + ".a" * 5000 + "]\n", "nested more than 64 levels deep"),
        ("[image]\n" + "a." * 5000 + "b = 1\n", "nested more than 64 levels deep"),
        ('[image]\nfov = """[[[[""""\nwidth = ' + "[" * 80 + "]" * 80 + "\n", "nested more than 64 levels deep"),
        ("[image]\nfov = 5" + "0" * (1 << 20) + "\n", "is more than the 1048576 bytes"),
        (b"[image]\nwidth = 64\n\xff\n", "not valid TOML: not UTF-8"),
    ],
)
def test_a_deep_or_large_config_is_one_line(tmp_path, capsys, text, words):
    config = tmp_path / "deep.toml"
    config.write_bytes(text if isinstance(text, bytes) else text.encode())
    _config_fails(tmp_path, capsys, config, str(config), words)


def test_a_config_that_is_a_directory_or_a_link_to_dev_zero_is_one_line(tmp_path, capsys):
    link = tmp_path / "zero.toml"
    link.symlink_to("/dev/zero")
    _config_fails(tmp_path, capsys, link, "this is a character device, not a dataset config")
    _config_fails(tmp_path, capsys, tmp_path, "this is a directory, not a dataset config")


def test_a_config_that_is_a_fifo_does_not_hang(tmp_path):
    """In a subprocess: a FIFO without a writer blocks an ordinary open() for ever."""
    fifo = tmp_path / "config.toml"
    os.mkfifo(fifo)
    out = tmp_path / "ds"
    argv = ["dataset", "--city", "default", "--samples", "2", "--out", str(out), "--config", str(fifo)]
    result = subprocess.run(
        [sys.executable, "-m", "cityshade", *argv],
        capture_output=True,
        text=True,
        timeout=60,
        env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
    )
    assert result.returncode == 2
    _one_line(result.stderr, "this is a FIFO, not a dataset config")
    assert not out.exists()


@pytest.mark.parametrize("value", ["nan", "+nan", "-nan", "inf", "+inf", "-inf"])
@pytest.mark.parametrize(
    "key", ["image.fov", "views.across", "views.pedestrian", "views.pedestrian_height", "views.aerial_pitch"]
)
def test_numbers_that_are_not_finite_are_refused(tmp_path, value, key):
    section, name = key.split(".")
    config = tmp_path / "c.toml"
    number = f"[{value}, 60.0]" if name == "aerial_pitch" else value
    config.write_text(f"[{section}]\n{name} = {number}\n")
    with pytest.raises(UsageError) as info:
        load_config(config)
    message = str(info.value)
    assert message.startswith(f"{config}: {key} = ") and "expected a finite number" in message, message
    assert "\n" not in message


def test_nan_fov_names_finite():
    with pytest.raises(UsageError, match=r"image.fov = nan: expected a finite number from 5.0 to 150.0"):
        parse_config({"image": {"fov": float("nan")}}, "c.toml")


# --- 6. caps, checked before anything is written --------------------------------------------------


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--samples", "1000000000000"], "--samples 1000000000000: give 1 to 1000000"),
        (["--samples", "0"], "--samples 0: give 1 to"),
        (["--samples", "2", "--workers", "1000"], "--workers 1000: give at most"),
        (["--samples", "2", "--workers", "0"], "--workers 0: give at least 1"),
        (["--samples", "2", "--seed", "-1"], "--seed -1: give 0 to"),
        (["--samples", "2", "--seed", str(2**70)], "--seed"),
    ],
)
def test_counts_past_their_caps_are_one_line_and_write_nothing(tmp_path, capsys, extra, words):
    out = tmp_path / "ds"
    code, err = _run(capsys, ["dataset", "--city", "default", "--out", out, *extra])
    assert code == 2
    _one_line(err, words)
    assert not out.exists()


def test_resume_with_more_samples_than_the_cap_writes_nothing(folder, capsys):
    before = _snapshot(folder)
    code, err = _run(capsys, ["dataset", "--city", "default", "--samples", "2000000", "--out", folder, "--resume"])
    assert code == 2 and "--samples 2000000" in err
    assert _snapshot(folder) == before


# --- addresses where no Ray cluster answers: one line, nothing written, no Ray started ------------


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _answering(reply: bytes):
    """127.0.0.1:PORT where a server sends `reply` to every connection, then closes it."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)

    def answer():
        while True:
            try:
                connection, _ = server.accept()
            except OSError:
                return
            with connection:
                connection.sendall(reply)

    threading.Thread(target=answer, daemon=True).start()
    yield f"127.0.0.1:{server.getsockname()[1]}"
    server.close()


@pytest.fixture
def not_ray():
    """Something answers there, but not a Ray cluster (an HTTP/1 server's reply)."""
    yield from _answering(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")


@pytest.mark.parametrize("where", ["free port", "not ray", "bad port", "no host"])
def test_an_address_without_a_ray_cluster_is_one_line_and_writes_nothing(tmp_path, capsys, not_ray, where):
    address = {
        "free port": f"127.0.0.1:{_free_port()}",
        "not ray": not_ray,
        "bad port": "127.0.0.1:99999",
        "no host": ":6379",
    }[where]
    out = tmp_path / "ds"
    code, err = _run(capsys, ["dataset", "--city", "default", "--samples", "2", "--out", out, "--address", address])
    assert code == 2
    _one_line(err, f"--address {address}: no Ray cluster answers there")
    assert not out.exists()
    import ray

    assert not ray.is_initialized()


def test_a_resumed_folder_with_an_unreachable_address_is_left_as_it_was(folder, capsys):
    (folder / row(1)["rgb"]).unlink()  # one sample to render: the run would need the cluster
    before = _snapshot(folder)
    code, err = _run(capsys, [*RESUME, "--out", folder, "--address", f"127.0.0.1:{_free_port()}"])
    assert code == 2
    _one_line(err, "no Ray cluster answers there")
    assert _snapshot(folder) == before


@pytest.fixture
def grpc_like():
    """Something answers HTTP/2's preface with a SETTINGS frame there, as Ray's GCS does."""
    yield from _answering(bytes([0, 0, 0, 4, 0, 0, 0, 0, 0]))


def test_a_failed_join_is_one_line_keeps_rays_log_off_and_writes_nothing(tmp_path, capfd, monkeypatch, grpc_like):
    """Past the probe, ray.init itself fails (here a stand-in that connects nowhere): one line, its
    C++ lines kept off stderr, the signal handlers from before it back, no dataset.json left."""
    import signal

    import ray

    from cityshade.dataset import generate

    def init(**options):
        assert options["address"] == grpc_like and options["logging_level"] == "ERROR"
        os.write(2, b"[2026-01-01 W 1 1] rpc_client.h:153: Failed to connect to GCS within 5 seconds.\n")
        signal.signal(signal.SIGTERM, lambda *_: None)  # as ray.init installs its own
        raise ConnectionError("Failed to connect to Ray cluster at 192.0.2.2:1")

    monkeypatch.setattr(ray, "init", init)
    monkeypatch.delenv("RAY_LOGGER_LEVEL", raising=False)
    before = signal.getsignal(signal.SIGTERM)
    out = tmp_path / "ds"
    with pytest.raises(UsageError) as info:
        generate(out, 2, parse_config({}), city="default", address=grpc_like, progress=False)
    message = str(info.value)
    assert message.startswith(f"--address {grpc_like}: Ray could not join the cluster there (Failed to connect")
    assert "RAY_LOGGER_LEVEL=info" in message and "\n" not in message
    assert "rpc_client" not in capfd.readouterr().err
    assert signal.getsignal(signal.SIGTERM) is before
    assert not out.exists()
