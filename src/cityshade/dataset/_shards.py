"""WebDataset tar shards of a dataset's complete samples: `shards/000000.tar`, ... each holding
`per_shard` samples in index order (the manifest's files and the optional ones each sample's JSON
lists), every file named `KEY.EXTENSION` with KEY the 7-digit sample
index. The tars are reproducible (sorted members, mtime 0, uid/gid 0) and each is written atomically.
Only regular files inside the dataset folder go into them (_manifest.sample_path)."""

from __future__ import annotations

import io
import os
import tarfile
from pathlib import Path

from ._manifest import FILES, extra_files_of, folder_file, read_manifest, read_sample_file
from ._sample import write_atomic


def _member(tar: tarfile.TarFile, name: str, data: bytes):
    info = tarfile.TarInfo(name)
    info.size, info.mtime, info.mode = len(data), 0, 0o644
    tar.addfile(info, io.BytesIO(data))


def write_shards(folder: Path, per_shard: int) -> list[Path]:
    """Writes the shards of every sample in the manifest; returns their paths. Shards left from an
    earlier run with more shards are removed."""
    folder = Path(folder)
    rows = read_manifest(folder)
    shards = folder_file(folder, "shards")
    paths = []
    for k in range(0, len(rows), per_shard):
        buffer = io.BytesIO()
        with tarfile.open(fileobj=buffer, mode="w", format=tarfile.USTAR_FORMAT) as tar:
            for row in rows[k : k + per_shard]:
                for name in FILES:
                    data = read_sample_file(folder, row, name)
                    _member(tar, os.path.basename(row[name]), data)
                extras = extra_files_of(row, data)  # the camera JSON, the last of FILES
                for name, path in sorted(extras.items()):
                    _member(tar, os.path.basename(path), read_sample_file(folder, {**row, name: path}, name))
        paths.append(folder / "shards" / f"{k // per_shard:06d}.tar")
        write_atomic(shards / paths[-1].name, buffer.getvalue())
    for stale in sorted(shards.glob("*.tar"))[len(paths) :]:
        stale.unlink()
    return paths
