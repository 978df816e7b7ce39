"""WebDataset tar shards of a dataset's complete samples: `shards/000000.tar`, ... each holding
`per_shard` samples in index order, every file named `KEY.EXTENSION` with KEY the 7-digit sample
index. The tars are reproducible (sorted members, mtime 0, uid/gid 0) and each is written atomically."""

from __future__ import annotations

import io
import tarfile
from pathlib import Path

from ._manifest import read_manifest
from ._sample import SUFFIXES, write_atomic


def _member(tar: tarfile.TarFile, name: str, data: bytes):
    info = tarfile.TarInfo(name)
    info.size, info.mtime, info.mode = len(data), 0, 0o644
    tar.addfile(info, io.BytesIO(data))


def write_shards(folder: Path, per_shard: int) -> list[Path]:
    """Writes the shards of every sample in the manifest; returns their paths. Shards left from an
    earlier run with more shards are removed."""
    folder = Path(folder)
    rows = read_manifest(folder)
    paths = []
    for k in range(0, len(rows), per_shard):
        buffer = io.BytesIO()
        with tarfile.open(fileobj=buffer, mode="w", format=tarfile.USTAR_FORMAT) as tar:
            for row in rows[k : k + per_shard]:
                for name in SUFFIXES:
                    path = folder / row[name]
                    _member(tar, path.name, path.read_bytes())
        paths.append(folder / "shards" / f"{k // per_shard:06d}.tar")
        write_atomic(paths[-1], buffer.getvalue())
    for stale in sorted((folder / "shards").glob("*.tar"))[len(paths) :]:
        stale.unlink()
    return paths
