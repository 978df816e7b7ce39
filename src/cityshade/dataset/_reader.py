"""Reading a dataset back for training: `Samples(DIR)` over a dataset folder (its manifest) or
`Samples(TAR or [TARs])` over its WebDataset shards, each item a dict of numpy arrays.

No torch is needed; a Samples is a map-style dataset (len and indexing) that torch's DataLoader
takes as it is, and its items hold only arrays and the index, which DataLoader's default collation
stacks. Every file is read as a capped regular file and decoded after its header is checked
(_arrays.py); the camera JSON of an item is `Samples.meta(i)`.
"""

from __future__ import annotations

import io
import json
import os
import tarfile
from pathlib import Path

import numpy as np
from PIL import Image

from ..errors import UsageError
from ._arrays import ArrayFileError, decode
from ._limits import MAX_SAMPLE_FILE_BYTES
from ._manifest import FILES, extra_files_of, read_manifest, read_sample_file, sample_error

# file extension (after the 7-digit key) -> item name; arrays of any of the writer's formats
NAMES = {
    "rgb.png": "rgb",
    "class.png": "class",
    "json": "meta",
    "depth.png": "kitti_depth",
    "labelIds.png": "label_ids",
    "trainIds.png": "train_ids",
    **{f"{name}.{ext}": name for name in ("depth", "distance", "normal", "instance") for ext in ("npz", "exr", "npy")},
}
INTEGER_ARRAYS = ("instance",)


def _image(data: bytes) -> np.ndarray:
    image = Image.open(io.BytesIO(data), formats=["PNG"])
    return np.asarray(image)


class SampleFileError(ValueError):
    """A file of a sample that cannot be read: its name (the manifest's column) and why."""

    def __init__(self, name: str, reason: str):
        super().__init__(f"{name}: {reason}")
        self.name, self.reason = name, reason


def _decoded(name: str, file_name: str, data: bytes) -> np.ndarray:
    if file_name.endswith(".png"):
        try:
            return _image(data)
        except (OSError, ValueError, SyntaxError, EOFError, Image.DecompressionBombError):
            raise ArrayFileError("not a readable PNG image") from None
    array = decode(data, file_name, "ui" if name in INTEGER_ARRAYS else "f")
    return array.astype(np.float32) if array.dtype == np.float16 else array  # normals, widened exactly


def item_from_files(files: dict[str, tuple[str, bytes]]) -> tuple[dict, dict]:
    """(item, camera JSON) from name -> (file name, bytes); raises SampleFileError."""
    try:
        meta = json.loads(files["meta"][1])
        item = {
            "index": int(meta["index"]),
            "K": np.asarray(meta["K"], np.float64).reshape(3, 3),
            "world_to_camera": np.asarray(meta["world_to_camera"], np.float64).reshape(4, 4),
        }
    except (ValueError, KeyError, TypeError, RecursionError):
        raise SampleFileError("meta", "not a sample's camera JSON") from None
    for name, (file_name, data) in files.items():
        if name != "meta":
            try:
                item[name] = _decoded(name, file_name, data)
            except ArrayFileError as exc:
                raise SampleFileError(name, str(exc)) from None
    return item, meta


class Samples:
    """A dataset folder's samples (by the manifest) or a list of its WebDataset shards, in index order."""

    def __init__(self, source: str | os.PathLike | list):
        sources = [Path(s) for s in source] if isinstance(source, (list, tuple)) else [Path(source)]
        self.folder = None
        if len(sources) == 1 and sources[0].is_dir():
            self.folder = sources[0]
            self.rows = read_manifest(self.folder)
        else:
            self.members = self._index_shards(sources)

    @staticmethod
    def _index_shards(paths: list[Path]) -> list[dict[str, tuple[Path, tarfile.TarInfo]]]:
        keyed: dict[str, dict] = {}
        for path in paths:
            if not path.is_file():
                raise UsageError(f"{path}: not a dataset folder or a WebDataset shard (.tar)")
            try:
                with tarfile.open(path) as tar:
                    for info in tar:
                        key, _, extension = info.name.rpartition("/")[2].partition(".")
                        if info.isfile() and extension in NAMES and info.size <= MAX_SAMPLE_FILE_BYTES:
                            keyed.setdefault(key, {})[NAMES[extension]] = (path, info)
            except (tarfile.TarError, OSError) as exc:
                raise UsageError(f"{path}: not a readable WebDataset shard ({type(exc).__name__})") from None
        return [keyed[key] for key in sorted(keyed) if "meta" in keyed[key]]

    def __len__(self) -> int:
        return len(self.rows) if self.folder is not None else len(self.members)

    def _files(self, i: int) -> dict[str, tuple[str, bytes]]:
        if self.folder is not None:
            row = self.rows[i]
            files = {name: (row[name], read_sample_file(self.folder, row, name)) for name in FILES}
            for name, path in extra_files_of(row, files["meta"][1]).items():
                files[name] = (path, read_sample_file(self.folder, {**row, name: path}, name))
            return files
        files, tars = {}, {}
        try:
            for name, (path, info) in self.members[i].items():
                tar = tars.get(path) or tars.setdefault(path, tarfile.open(path))
                files[name] = (info.name, tar.extractfile(info).read())
        finally:
            for tar in tars.values():
                tar.close()
        return files

    def _read(self, i: int) -> tuple[dict, dict]:
        if not -len(self) <= i < len(self):
            raise IndexError(f"sample {i} of {len(self)}")
        i %= len(self)
        files = self._files(i)
        try:
            return item_from_files(files)
        except SampleFileError as exc:
            if self.folder is not None:
                raise sample_error(self.folder, self.rows[i], exc.name, exc.reason) from None
            shard, member = self.members[i][exc.name]
            raise UsageError(f"{shard}: {member.name}: {exc.reason}") from None

    def __getitem__(self, i: int) -> dict:
        """Sample i: `index`, `rgb` (HxWx3 uint8), `depth` and `distance` (HxW float32 metres),
        `normal` (HxWx3), `class` (HxW uint8), `instance` (HxWx2 uint32: building, part), `K`,
        `world_to_camera`, and the optional `kitti_depth`, `label_ids`, `train_ids`."""
        return self._read(i)[0]

    def meta(self, i: int) -> dict:
        """Sample i's camera JSON (camera, place, time, sun, instances' source ids)."""
        return self._read(i)[1]

    def __iter__(self):
        return (self[i] for i in range(len(self)))
