"""Fuzzers for `cityshade dataset`'s inputs: hostile configs (TOML) and damaged dataset folders.
The property: a config loads (finite values within their ranges) or is one line naming the file;
a folder's resume check, shards, preview and record check succeed or are one line, and nothing
outside the folder is read (Python's `open` audit event), quoted, sized or changed. Ray is never
started: these are the layers `--resume`, `--shards` and `--preview` run before and without it.

A small budget runs with every `make test`; `make fuzz` runs the `fuzz`-marked tests for
CITYSHADE_FUZZ_SECONDS seconds each (docs/robustness.md)."""

from __future__ import annotations

import io
import json
import math
import os
import sys
import tarfile
import tempfile
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import given
from hypothesis import strategies as st

import cityshade
from cityshade.dataset import DEFAULTS, load_config, sample_files, write_preview, write_shards
from cityshade.dataset.testing import COLUMNS, FILES, check_record, complete_rows
from cityshade.errors import UsageError
from dataset_folders import make_folder, npz, opened_files, record, write_rows
from fuzzing import LARGE, SMALL, for_a_while

SECRET = b"cityshade-fuzz-secret\n" * 333  # 7326 bytes: neither its text nor its size may show

# ------------------------------------------------------------------ configs

number = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1000, 5000),
    st.integers(-(10**30), 10**30),
    st.integers(0, 5000),
    st.sampled_from([float("nan"), float("inf"), float("-inf"), 0, -0.0, 1e308, 5e-324]),
)
scalar = st.one_of(number, st.booleans(), st.text(max_size=8), st.sampled_from(["2025-03-01", "2025-13-40", "lamp"]))
value = st.recursive(
    scalar,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=4), inner, max_size=3),
    max_leaves=12,
)


def toml(item) -> str:
    """A Python value as TOML (floats as TOML writes nan and inf, strings and keys JSON-quoted)."""
    if isinstance(item, bool):
        return "true" if item else "false"
    if isinstance(item, float):
        return "nan" if math.isnan(item) else ("inf" if item > 0 else "-inf") if math.isinf(item) else repr(item)
    if isinstance(item, int):
        return str(item)
    if isinstance(item, str):
        return item if item[:4].isdigit() and item.count("-") == 2 else json.dumps(item)  # dates stay dates
    if isinstance(item, list):
        return "[" + ", ".join(toml(v) for v in item) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml(v)}" for k, v in item.items()) + "}"


TOKENS = ["[", "]", "{", "}", "=", ",", '"', "'", '"""', "'''", "#", "\n", ".", "nan", "inf", "\\", "\x00"]


@st.composite
def configs(draw) -> bytes:
    lines = []
    for _ in range(draw(st.integers(0, 5))):
        section = draw(st.sampled_from([*DEFAULTS, "camera", "image.sub"]))
        lines.append(f"[{section}]")
        keys = list(DEFAULTS.get(section, {})) + ["colour", "a.b.c"]
        for _ in range(draw(st.integers(0, 4))):
            key = draw(st.sampled_from(keys))
            default = DEFAULTS.get(section, {}).get(key)
            if default is not None and draw(st.booleans()):  # a plausible value near the default
                item = default if not isinstance(default, (int, float)) or isinstance(default, bool) else draw(number)
            else:
                item = draw(value)
            lines.append(f"{key} = {toml(item)}")
    text = "\n".join(lines) + "\n"
    for _ in range(draw(st.integers(0, 3))):
        at = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["token", "deep", "cut", "text"]))
        if kind == "token":
            text = text[:at] + draw(st.sampled_from(TOKENS)) + text[at:]
        elif kind == "deep":
            n = draw(st.sampled_from([2, 63, 64, 65, 500, 5000]))
            opener = draw(st.sampled_from(["[", "{a = ", "a."]))
            text = text[:at] + opener * n + text[at:]
        elif kind == "cut":
            text = text[:at]
        else:
            text = text[:at] + draw(st.text(max_size=6)) + text[at:]
    data = text.encode("utf-8", "surrogatepass")
    if draw(st.integers(0, 9)) == 0:
        data += b"\xff"
    return data


def check_config(data: bytes, folder: Path):
    path = folder / "fuzz.toml"
    path.write_bytes(data)
    try:
        config = load_config(path)
    except UsageError as exc:
        message = str(exc)
        assert message.startswith(f"{path}: ") and "\n" not in message and len(message) < 1000, message
        return
    assert 8 <= config.width <= 4096 and 8 <= config.height <= 4096 and 5 <= config.fov <= 150
    numbers = [config.fov, config.pedestrian_height, config.across, *config.vehicle_height, *config.hours]
    assert all(math.isfinite(v) for v in numbers + [*config.aerial_height, *config.aerial_pitch])


@SMALL
@given(configs())
def test_hostile_configs_small(data):
    with tempfile.TemporaryDirectory() as folder:
        check_config(data, Path(folder))


# ------------------------------------------------------------------ damaged dataset folders

HOSTILE_PATHS = [
    "{secret}",
    "/etc/passwd",
    "/proc/self/environ",
    "/dev/zero",
    "../secret.txt",
    "../../../../../../etc/passwd",
    "samples/../../secret.txt",
    "samples/../samples/0000000.rgb.png",
    "",
    ".",
    "samples",
    "\x00",
    "a" * 5000,
    "samples/" + "é" * 40,
    "dataset.json",
    "manifest.parquet",
]
LINK_TARGETS = ["{secret}", "{outside}", "/dev/zero", "/etc/passwd", "dangling", "itself", "dataset.json"]
COLUMN_TYPES = ["strings", "floats", "integers", "nulls", "booleans", "lists", "large strings"]


def _arrow(kind: str, n: int, draw):
    if kind == "strings":
        return pa.array([draw(st.text(max_size=6)) for _ in range(n)])
    if kind == "large strings":
        return pa.array([draw(st.sampled_from(HOSTILE_PATHS)) for _ in range(n)], pa.large_string())
    if kind == "floats":
        return pa.array([draw(st.floats(allow_nan=True)) for _ in range(n)])
    if kind == "integers":
        return pa.array([draw(st.integers(-(2**63), 2**63 - 1)) for _ in range(n)], pa.int64())
    if kind == "nulls":
        return pa.nulls(n)
    if kind == "booleans":
        return pa.array([draw(st.booleans()) for _ in range(n)])
    return pa.array([[1, 2]] * n)


@st.composite
def damages(draw) -> tuple[int, list]:
    samples = draw(st.integers(1, 3))
    steps = []
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(
            st.sampled_from(
                ["path", "link", "fifo", "content", "remove", "type", "drop", "index", "manifest", "record"]
            )
        )
        where = (draw(st.integers(0, samples - 1)), draw(st.sampled_from(FILES)))
        if kind == "path":
            steps.append((kind, where, draw(st.sampled_from(HOSTILE_PATHS) | st.text(max_size=12))))
        elif kind == "link":
            steps.append((kind, where, draw(st.sampled_from(LINK_TARGETS))))
        elif kind == "content":
            content = draw(
                st.one_of(
                    st.binary(max_size=64),
                    st.just(b"\x89PNG\r\n\x1a\n" + bytes(40)),
                    st.just(
                        b"\x93NUMPY\x01\x00v\x00{'descr': '<f4', 'fortran_order': False, 'shape': (99999, 99999), }"
                    ),
                    st.just(npz(np.zeros((3, 5), "complex64"))),
                    st.just("other sample"),
                    st.just("cut"),
                )
            )
            steps.append((kind, where, content))
        elif kind == "type":
            column = draw(st.sampled_from(list(COLUMNS)))
            steps.append((kind, column, _arrow(draw(st.sampled_from(COLUMN_TYPES)), samples, draw)))
        elif kind == "drop":
            steps.append((kind, draw(st.sampled_from(list(COLUMNS)))))
        elif kind == "index":
            steps.append((kind, draw(st.lists(st.integers(-5, 2_000_000), min_size=samples, max_size=samples))))
        elif kind == "manifest":
            steps.append(
                (kind, draw(st.sampled_from(["cut", "flip", "empty", "append", "fifo"])), draw(st.integers(0, 10**6)))
            )
        elif kind == "record":
            steps.append((kind, draw(st.sampled_from(["deep", "list", "garbage", "seed", "fifo", "link", "huge"]))))
        else:
            steps.append((kind, where))
    return samples, steps


def _apply(folder: Path, secret: Path, outside: Path, rows: list[dict], step, draw_table):
    """One damage to the folder: a sample's file or manifest entry, the manifest's table or bytes,
    or dataset.json."""
    kind = step[0]
    resolve = {"{secret}": str(secret), "{outside}": str(outside)}
    if kind in ("path", "link", "fifo", "content", "remove"):
        _damage_sample(folder, resolve, rows, step, draw_table)
    elif kind in ("type", "drop", "index"):
        _damage_table(folder / "manifest.parquet", step)
    elif kind == "manifest":
        _damage_manifest_bytes(folder / "manifest.parquet", step)
    else:
        _damage_record(folder / "dataset.json", secret, step)


def _damage_sample(folder: Path, resolve: dict, rows: list[dict], step, draw_table):
    kind = step[0]
    (k, column) = step[1]
    if kind == "path":
        rows[k][column] = resolve.get(step[2], step[2])
        draw_table(rows)
        return
    path = folder / sample_files(k)[column]  # the file itself, whatever the manifest says now
    assert str(path).startswith(str(folder) + os.sep)
    if path.is_symlink() or path.is_file():
        path.unlink()
    elif path.exists():
        return
    if kind == "link":
        target = {
            "dangling": str(folder / "nowhere"),
            "itself": str(path),
            "dataset.json": str(folder / "dataset.json"),
        }
        path.symlink_to(resolve.get(step[2], target.get(step[2], step[2])))
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "content":
        content = step[2]
        if content == "other sample":
            other = folder / sample_files((k + 1) % len(rows))[FILES[(FILES.index(column) + 1) % len(FILES)]]
            content = other.read_bytes() if other.is_file() and not other.is_symlink() else b""
        elif content == "cut":
            content = b"\x89PNG\r\n\x1a\n\x00\x00"
        path.write_bytes(content)


def _damage_table(manifest: Path, step):
    kind = step[0]
    if not manifest.is_file() or manifest.is_symlink():  # pyarrow would wait on a FIFO for ever
        return
    try:
        table = pq.read_table(manifest)
    except Exception:  # an earlier step broke the file: this one has nothing to work on
        return
    if kind == "drop":
        if step[1] in table.column_names:
            table = table.drop_columns([step[1]])
    elif kind == "type":
        if step[1] in table.column_names and len(table) == len(step[2]):
            table = table.set_column(table.column_names.index(step[1]), step[1], step[2])
    elif "index" in table.column_names and len(table) == len(step[1]):
        table = table.set_column(table.column_names.index("index"), "index", pa.array(step[1], pa.int64()))
    pq.write_table(table, manifest)


def _damage_manifest_bytes(manifest: Path, step):
    how, at = step[1], step[2]
    if not manifest.is_file() or manifest.is_symlink():
        return
    data = manifest.read_bytes()
    if not data:
        return
    if how == "fifo":
        manifest.unlink()
        os.mkfifo(manifest)
        return
    data = {
        "cut": data[: at % max(1, len(data))],
        "flip": data[: at % len(data)] + bytes([data[at % len(data)] ^ 0x5A]) + data[at % len(data) + 1 :],
        "empty": b"",
        "append": data + b"PAR1" * 3,
    }[how]
    manifest.write_bytes(data)


def _damage_record(path: Path, secret: Path, step):
    how = step[1]
    if os.path.lexists(path):  # a file, a link or a FIFO an earlier step left
        path.unlink()
    if how == "fifo":
        os.mkfifo(path)
    elif how == "link":
        path.symlink_to(secret)
    else:
        path.write_text(
            {
                "deep": "[" * 3000 + "]" * 3000,
                "list": "[1]",
                "garbage": '{"seed": 0, ',
                "seed": json.dumps({**record(), "seed": 1}),
                "huge": json.dumps({**record(), "source": "x" * (2 << 20)}),
            }[how]
        )


def _within(path: str, folder: str) -> bool:
    return path == folder or path.startswith(folder + os.sep)


def _library(path: str) -> bool:
    """Files Python itself may open meanwhile: modules, plugins, time zones."""
    roots = {sys.prefix, sys.base_prefix, os.path.dirname(os.path.dirname(cityshade.__file__))}
    return any(path.startswith(os.path.realpath(root) + os.sep) for root in roots) or path.startswith("/usr/share/")


def check_folder(samples: int, steps: list, root: Path, draw):
    folder, secret, outside = root / "ds", root / "secret.txt", root / "outside"
    secret.write_bytes(SECRET)
    outside.mkdir()
    (outside / "note").write_bytes(SECRET)
    rows = make_folder(folder, samples)

    def draw_table(changed):
        manifest = folder / "manifest.parquet"
        if os.path.lexists(manifest) and not manifest.is_file():  # pyarrow would wait on a FIFO for ever
            manifest.unlink() if not manifest.is_dir() or manifest.is_symlink() else os.rmdir(manifest)
        write_rows(folder, changed)

    for step in steps:
        _apply(folder, secret, outside, rows, step, draw_table)
    inside = os.path.realpath(folder)
    with opened_files() as seen:
        for consumer in (
            lambda: complete_rows(folder),
            lambda: check_record(folder, record(), resume=True),
            lambda: write_shards(folder, draw(st.integers(1, 3))),
            lambda: write_preview(folder),
        ):
            try:
                consumer()
            except UsageError as exc:
                message = str(exc)
                assert "\n" not in message and "cityshade-fuzz-secret" not in message, message
                assert "7326" not in message and len(message) < 2000, message
    strays = [p for p in seen if isinstance(p, str) and not _within(p, inside) and not _library(p)]
    assert not strays, f"read outside the dataset folder: {strays}"
    assert secret.read_bytes() == SECRET and sorted(p.name for p in outside.iterdir()) == ["note"]
    assert sorted(p.name for p in root.iterdir()) == ["ds", "outside", "secret.txt"]
    for shard in (folder / "shards").glob("*.tar") if (folder / "shards").is_dir() else ():
        with tarfile.open(shard) as tar:
            for member in tar.getmembers():
                assert b"cityshade-fuzz-secret" not in tar.extractfile(member).read()


def _run_folder(case, data):
    samples, steps = case
    with tempfile.TemporaryDirectory() as root:
        check_folder(samples, steps, Path(root), data.draw)


@SMALL
@given(damages(), st.data())
def test_damaged_dataset_folders_small(case, data):
    _run_folder(case, data)


# ------------------------------------------------------------------ the long runs (make fuzz)


@pytest.mark.fuzz
def test_hostile_configs_long():
    def run(data):
        with tempfile.TemporaryDirectory() as folder:
            check_config(data, Path(folder))

    for_a_while(LARGE(given(configs())(run)))


@pytest.mark.fuzz
def test_damaged_dataset_folders_long():
    for_a_while(LARGE(given(damages(), st.data())(_run_folder)))


def test_the_folder_generator_reaches_every_consumer():
    """The unchanged folder passes every consumer: the fuzzer's refusals come from its damage."""
    with tempfile.TemporaryDirectory() as root:
        folder = Path(root) / "ds"
        make_folder(folder, 3)
        assert sorted(complete_rows(folder)) == [0, 1, 2]
        check_record(folder, record(), resume=True)
        assert len(write_shards(folder, 2)) == 2
        assert write_preview(folder).is_file()
        assert io.BytesIO((folder / "preview.png").read_bytes()).read(4) == b"\x89PNG"
