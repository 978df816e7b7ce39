"""The dataset folder's records: `dataset.json` (what the samples are drawn from, the seed and the
settings: --resume refuses anything else) and `manifest.parquet` (one row per complete sample)."""

from __future__ import annotations

import io
import json
from pathlib import Path

from ..errors import UsageError

MANIFEST = "manifest.parquet"
RECORD = "dataset.json"


def read_manifest(folder: Path) -> list[dict]:
    """The manifest's rows, by sample index; [] without a manifest."""
    import pyarrow.parquet as pq

    path = Path(folder) / MANIFEST
    if not path.exists():
        return []
    return sorted(pq.read_table(path).to_pylist(), key=lambda row: row["index"])


def write_manifest(folder: Path, rows: list[dict]):
    import pyarrow as pa
    import pyarrow.parquet as pq

    from ._sample import write_atomic

    buffer = io.BytesIO()
    pq.write_table(pa.Table.from_pylist(sorted(rows, key=lambda row: row["index"])), buffer)
    write_atomic(Path(folder) / MANIFEST, buffer.getvalue())


def check_record(folder: Path, record: dict, resume: bool):
    """Writes the record of a new dataset; on --resume, refuses a folder made differently, naming
    the first setting that differs. Without --resume a folder that holds a dataset is refused."""
    from ._sample import write_atomic

    path = Path(folder) / RECORD
    if path.exists():
        if not resume:
            raise UsageError(f"{folder} already holds a dataset; add --resume to complete it or choose another --out")
        try:
            old = json.loads(path.read_text())
        except (OSError, ValueError):
            raise UsageError(f"{path}: unreadable dataset record; choose another --out") from None
        for key in sorted(set(old) | set(record)):
            if old.get(key) != record.get(key):
                raise UsageError(
                    f"--resume: {folder} was made with {key} = {old.get(key)!r}, "
                    f"this run has {record.get(key)!r}; use the same settings or another --out"
                )
        return
    write_atomic(path, json.dumps(record, indent=1, sort_keys=True).encode())
