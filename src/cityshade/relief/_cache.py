"""Compressed detail maps cached on disk by the content hash of the maps: a style's maps are
factorised once per machine, not on every city load (and, by the hash of their inputs, the
arrays that are slow to derive: a style's window openings).

The folder is $CITYSHADE_CACHE_DIR, else $XDG_CACHE_HOME/cityshade, else ~/.cache/cityshade. A
file that cannot be read back (damaged, truncated, another version) or that holds other maps than
its name says (the digests in its header differ) is rebuilt and replaced, never trusted.
"""

from __future__ import annotations

import hashlib
import os
import zipfile
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import CityshadeError
from ._compress import MAP_NAMES, CompressedFacade, compress, detail_matrices, digest
from ._format import VERSION, read_compressed, write_compressed
from ._maps import DetailMaps

CACHE_ENV = "CITYSHADE_CACHE_DIR"


def cache_dir() -> Path:
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "cityshade"


def cache_key(maps: DetailMaps, method: str) -> str:
    """The file's name: the format version, the method, the texel and depth unit and D and M."""
    parts = [
        f"cfdm{VERSION}",
        method,
        repr(maps.texel),
        repr(maps.depth_unit),
        digest(maps.depth),
        digest(maps.material),
    ]
    return hashlib.sha256("/".join(parts).encode()).hexdigest()[:32]


def cached_compress(maps: DetailMaps, method: str, source: str = "facade") -> tuple[CompressedFacade, bool]:
    """The maps factorised with `method`, from the cache when a sound entry exists; returns the
    factorisation and whether it came from the cache."""
    path = cache_dir() / f"relief-{method}-{cache_key(maps, method)}.cfdm"
    expected = {name: digest(matrix) for name, matrix in detail_matrices(maps)[0].items()}
    if path.is_file():
        try:
            facade = read_compressed(path)
        except (CityshadeError, OSError):
            facade = None  # damaged or foreign: rebuilt below
        if facade is not None and facade.method == method and all(facade.digests[n] == expected[n] for n in MAP_NAMES):
            return facade, True
    facade = compress(maps, method, source=source)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_compressed(path, facade)
    except OSError:
        pass  # a read-only cache only costs the factorisation next time
    return facade, False


def smallest_compression(maps: DetailMaps, source: str = "facade") -> CompressedFacade:
    """BMF or SVD, whichever takes fewer bytes on the GPU (each cached)."""
    options = [cached_compress(maps, method, source)[0] for method in ("bmf", "svd")]
    return min(options, key=lambda f: sum(f.nbytes().values()))


def cached_arrays(
    name: str, key: str, names: tuple[str, ...], build: Callable[[], dict[str, np.ndarray]]
) -> dict[str, np.ndarray]:
    """build()'s arrays (named `names`), from `name-key.npz` in the cache when it holds exactly
    those arrays and reads back (zip checks each member's CRC); else built, written beside it and
    renamed into place."""
    path = cache_dir() / f"{name}-{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as data:
            if sorted(data.files) == sorted(names):
                return {k: data[k] for k in names}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):
        pass  # absent, damaged or foreign: rebuilt below
    arrays = build()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        with open(partial, "wb") as f:
            np.savez(f, **arrays)
        os.replace(partial, path)
    except OSError:
        pass  # a read-only cache only costs the work next time
    return arrays
