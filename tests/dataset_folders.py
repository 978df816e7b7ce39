"""Dataset folders made without Ray or a renderer, for the tests of hostile and damaged folders:
the files and manifest rows `cityshade dataset --city default --seed 0` (default config) would
write, with tiny images, so --resume finds them complete and renders nothing."""

from __future__ import annotations

import contextlib
import io
import json
import os
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
from PIL import Image

from cityshade.dataset import parse_config, sample_files

SIZE = (8, 6)  # width, height


def record(seed: int = 0) -> dict:
    return {"source": "city:default", "seed": seed, **parse_config({}).settings()}


def png(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, format="PNG")
    return buffer.getvalue()


def npz(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.savez_compressed(buffer, array=array)
    return buffer.getvalue()


def sample_bytes(index: int, size=SIZE) -> dict[str, bytes]:
    w, h = size
    rng = np.random.default_rng(index)
    return {
        "rgb": png(rng.integers(0, 255, (h, w, 3), dtype=np.uint8)),
        "depth": npz(rng.uniform(1, 100, (h, w)).astype(np.float32)),
        "distance": npz(rng.uniform(1, 100, (h, w)).astype(np.float32)),
        "normal": npz(np.zeros((h, w, 3), np.float16)),
        "class": png(rng.integers(0, 17, (h, w), dtype=np.uint8)),
        "instance": npz(rng.integers(0, 3, (h, w, 2)).astype(np.uint32)),
        "meta": json.dumps(
            {
                "index": index,
                "eye": [0.0, 1.7, 0.0],
                "local_time": "12:00",
                "width": w,
                "height": h,
                "K": [[5.0, 0.0, (w - 1) / 2], [0.0, 5.0, (h - 1) / 2], [0.0, 0.0, 1.0]],
                "world_to_camera": np.identity(4).tolist(),
                "files": {name: Path(path).name for name, path in sample_files(index).items()},
            }
        ).encode(),
    }


def row(index: int) -> dict:
    return {
        "index": index,
        "kind": "pedestrian",
        **sample_files(index),
        "lon": None,
        "lat": None,
        "height_m": 1.7,
        "heading_deg": 90.0,
        "pitch_deg": 2.0,
        "date": None,
        "local_time": "12:00",
        "sun_elevation": 30.0,
        "sun_azimuth": 180.0,
    }


def write_rows(folder: Path, rows: list[dict]):
    pq.write_table(pa.Table.from_pylist(rows), Path(folder) / "manifest.parquet")


def make_folder(folder: Path, samples: int = 2) -> list[dict]:
    """A complete dataset folder of `samples` samples; returns its manifest rows."""
    folder = Path(folder)
    (folder / "samples").mkdir(parents=True)
    (folder / "dataset.json").write_text(json.dumps(record(), indent=1, sort_keys=True))
    rows = [row(i) for i in range(samples)]
    for r in rows:
        for name, data in sample_bytes(r["index"]).items():
            (folder / r[name]).write_bytes(data)
    write_rows(folder, rows)
    return rows


_recording: list[set] = []


def _audit(event, args):
    if event == "open" and _recording and isinstance(args[0], (str, bytes, os.PathLike)):
        _recording[-1].add(os.path.realpath(args[0]))


@contextlib.contextmanager
def opened_files():
    """The real paths of the files Python opens in the block (the `open` audit event: open(),
    os.open, io.open_code)."""
    if not _hook:
        sys.addaudithook(_audit)  # stays for the session; records only inside this block
        _hook.append(True)
    seen: set = set()
    _recording.append(seen)
    try:
        yield seen
    finally:
        _recording.pop()


_hook: list = []
