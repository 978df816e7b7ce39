"""The dataset folder's records: `dataset.json` (what the samples are drawn from, the seed and the
settings: --resume refuses anything else) and `manifest.parquet` (one row per complete sample).

A dataset folder may come from anyone, so both are read as capped regular files inside the folder
and checked before use: a damaged, truncated or foreign manifest, a column missing or of the wrong
type, or a path that leaves the folder (absolute, '..', a symbolic link out) is one line naming the
file, and a path never reads anything outside the folder (_files.inside_folder)."""

from __future__ import annotations

import io
import json
import os
from pathlib import Path

from .._files import InputError, inside_folder, read_input_bytes
from .._json import nesting_depth
from ..errors import UsageError
from ._limits import (
    MAX_MANIFEST_BYTES,
    MAX_MANIFEST_UNPACKED,
    MAX_NESTING,
    MAX_RECORD_BYTES,
    MAX_SAMPLE_FILE_BYTES,
    MAX_SAMPLES,
    shown,
    shown_key,
)
from ._sample import SUFFIXES, write_atomic

MANIFEST = "manifest.parquet"
RECORD = "dataset.json"
FILES = tuple(SUFFIXES)  # the columns that hold a sample's file paths, relative to the folder
# column -> what it holds: "index" integers, "path" strings (never null), "text" strings or null,
# "number" integers, floats or null (lon and lat are null over the built-in cities)
COLUMNS = {
    "index": "index",
    "kind": "text",
    **{name: "path" for name in FILES},
    "lon": "number",
    "lat": "number",
    "height_m": "number",
    "heading_deg": "number",
    "pitch_deg": "number",
    "date": "text",
    "local_time": "text",
    "sun_elevation": "number",
    "sun_azimuth": "number",
}
REDO = "move it away and run cityshade dataset --resume with the same settings (unlisted samples are rendered again)"


def folder_file(folder: Path, name: str) -> Path:
    """One of the folder's own files (the manifest, the record, the shards, the preview), refused
    when a symbolic link takes it out of the folder."""
    return inside_folder(folder, name, str(Path(folder) / name))


def sample_path(folder: Path, row: dict, column: str) -> Path:
    """The file a manifest row names in `column`, confined to the folder."""
    return inside_folder(
        folder, row[column], f"{Path(folder) / MANIFEST}: row of sample {row['index']}, column {column}"
    )


def sample_error(folder: Path, row: dict, column: str, reason: str) -> UsageError:
    """One line about a sample's file that cannot be used: the manifest row, the column, why, what to do."""
    return UsageError(
        f"{Path(folder) / MANIFEST}: row of sample {row['index']}, column {column}: {reason}; remove the file "
        "and run cityshade dataset --resume with the same settings to render the sample again"
    )


def read_sample_file(folder: Path, row: dict, column: str) -> bytes:
    """The bytes of the file a manifest row names: a capped regular file inside the folder."""
    try:
        return read_input_bytes(sample_path(folder, row, column), MAX_SAMPLE_FILE_BYTES, "sample file")
    except InputError as exc:
        raise sample_error(folder, row, column, exc.reason) from None


def extra_files_of(row: dict, meta: bytes) -> dict[str, str]:
    """The optional files (KITTI depth, Cityscapes ids) a sample's camera JSON lists beside the
    manifest's: name -> path relative to the folder ({} for JSON that lists none)."""
    try:
        files = json.loads(meta).get("files", {})
    except (ValueError, AttributeError, RecursionError):
        return {}
    if not isinstance(files, dict):
        return {}
    return {
        name: f"samples/{name_on_disk}"
        for name, name_on_disk in files.items()
        if name not in FILES
        and isinstance(name_on_disk, str)
        and name_on_disk.startswith(f"{row['index']:07d}.")
        and "/" not in name_on_disk
    }


def _column_fits(kind: str, arrow_type) -> bool:
    import pyarrow as pa

    if pa.types.is_null(arrow_type):
        return kind in ("text", "number")
    if kind == "index":
        return pa.types.is_integer(arrow_type)
    if kind in ("path", "text"):
        return pa.types.is_string(arrow_type) or pa.types.is_large_string(arrow_type)
    return pa.types.is_integer(arrow_type) or pa.types.is_floating(arrow_type)


def _read_table(path: Path):
    """The manifest's table, or UsageError: sizes checked on the file's footer before any column is read."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    data = read_input_bytes(path, MAX_MANIFEST_BYTES, "dataset manifest")
    try:
        reader = pq.ParquetFile(pa.BufferReader(data))
        meta = reader.metadata
        if meta.num_rows > MAX_SAMPLES:
            raise UsageError(f"{path}: {meta.num_rows} rows, more than the {MAX_SAMPLES} samples a dataset may have")
        unpacked = sum(meta.row_group(k).total_byte_size for k in range(meta.num_row_groups))
        if unpacked > MAX_MANIFEST_UNPACKED:
            raise UsageError(
                f"{path}: {unpacked} bytes unpacked, more than the {MAX_MANIFEST_UNPACKED} a manifest may have"
            )
        names = set(reader.schema_arrow.names)
        missing = [name for name in COLUMNS if name not in names]
        if missing:
            raise UsageError(f"{path}: no column {', '.join(missing)}; not a manifest of cityshade dataset; {REDO}")
        table = reader.read(columns=list(COLUMNS), use_threads=False)  # no pool threads left at exit
    except (pa.ArrowException, OSError, ValueError, TypeError, IndexError, KeyError, MemoryError) as exc:
        raise UsageError(f"{path}: not a readable Parquet manifest ({type(exc).__name__}); {REDO}") from None
    for name, kind in COLUMNS.items():
        column = table.column(name)
        if not _column_fits(kind, column.type):
            raise UsageError(f"{path}: column {name} holds {shown(str(column.type))}, not {kind}s; {REDO}")
        if kind in ("index", "path") and column.null_count:
            raise UsageError(f"{path}: column {name} has empty (null) entries; {REDO}")
    return table


def read_manifest(folder: Path) -> list[dict]:
    """The manifest's rows, by sample index; [] without a manifest."""
    import pyarrow.compute as pc

    path = Path(folder) / MANIFEST
    if not os.path.lexists(path):
        return []
    table = _read_table(folder_file(folder, MANIFEST))
    if len(table):
        index = table.column("index")
        low, high = pc.min(index).as_py(), pc.max(index).as_py()
        if low < 0 or high >= MAX_SAMPLES:
            raise UsageError(
                f"{path}: sample index {low if low < 0 else high} is outside 0 to {MAX_SAMPLES - 1}; {REDO}"
            )
        if pc.count_distinct(index).as_py() != len(table):
            raise UsageError(f"{path}: a sample index is listed twice; {REDO}")
    return sorted(table.to_pylist(), key=lambda row: row["index"])


def complete_rows(folder: Path) -> dict[int, dict]:
    """The manifest's rows whose six files exist (inside the folder), by sample index: the samples
    --resume does not render again."""
    folder = Path(folder)
    return {
        row["index"]: row
        for row in read_manifest(folder)
        if all(os.path.exists(sample_path(folder, row, name)) for name in FILES)
    }


def write_manifest(folder: Path, rows: list[dict]):
    import pyarrow as pa
    import pyarrow.parquet as pq

    buffer = io.BytesIO()
    pq.write_table(pa.Table.from_pylist(sorted(rows, key=lambda row: row["index"])), buffer)
    write_atomic(folder_file(folder, MANIFEST), buffer.getvalue())


def read_record(folder: Path) -> dict | None:
    """The folder's dataset.json, or None without one; one line if it cannot be a record."""
    path = Path(folder) / RECORD
    if not os.path.lexists(path):
        return None
    data = read_input_bytes(folder_file(folder, RECORD), MAX_RECORD_BYTES, "dataset record")
    unreadable = f"{path}: unreadable dataset record"
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise UsageError(f"{unreadable} (not UTF-8); choose another --out") from None
    if nesting_depth(text) > MAX_NESTING:
        raise UsageError(f"{unreadable} (nested more than {MAX_NESTING} levels deep); choose another --out")
    try:
        record = json.loads(text)
    except (ValueError, RecursionError):
        raise UsageError(f"{unreadable} (not JSON); choose another --out") from None
    if not isinstance(record, dict):
        raise UsageError(f"{unreadable} (not a JSON object); choose another --out")
    return record


def check_record(folder: Path, record: dict, resume: bool):
    """Refuses a folder that holds a dataset without --resume and, on --resume, one made
    differently, naming the first setting that differs. Writes nothing."""
    old = read_record(folder)
    if old is None:
        return
    if not resume:
        raise UsageError(f"{folder} already holds a dataset; add --resume to complete it or choose another --out")
    for key in sorted(set(old) | set(record)):
        if old.get(key) != record.get(key):
            raise UsageError(
                f"--resume: {folder} was made with {shown_key(key)} = {shown(old.get(key))}, "
                f"this run has {shown(record.get(key))}; use the same settings or another --out"
            )


def write_record(folder: Path, record: dict):
    """Writes the record of a new dataset (an existing one was checked by check_record)."""
    if read_record(folder) is None:
        write_atomic(folder_file(folder, RECORD), json.dumps(record, indent=1, sort_keys=True).encode())
