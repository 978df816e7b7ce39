"""A city's buildings cut into square tiles on disk, for streaming (docs/scale.md, "Streaming").

A cache folder holds `manifest.json` (format, cityshade version, vertex and record layouts, the
source file's name, size and SHA-256, and per tile its file, bounds, counts, bytes and SHA-256),
`city.pickle` (the City without the tiles' vertices: masses, ground, trees, lamps, viewpoints; the
building records with their facades assigned; the cull pass's boxes in the whole city's order, each
box's first vertex counted within its tile) and `tiles/NNNNN.npy` (each tile's vertices, its
buildings one after another in box order). A tile is the buildings whose box centre falls in one
square of `tile_size` metres.

Anything that does not match (another format, cityshade version, vertex layout or source file; a
missing, truncated or altered file) raises CacheProblem with one line saying what; the caller
rebuilds the cache from the source or reports the line.
"""

from __future__ import annotations

import hashlib
import io
import json
import pickle
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._files import atomic_folder
from ..errors import CityshadeError
from ..scene import BUILDING_DTYPE, VERTEX_DTYPE, City
from ._city_gpu import CityBuildings

FORMAT = 1
TILE_SIZE = 256.0  # metres: about a district of a dozen blocks
MANIFEST = "manifest.json"
CITY_FILE = "city.pickle"
TILE_FOLDER = "tiles"
HASH_BLOCK = 1 << 20


class CacheProblem(CityshadeError):
    """A tile cache that cannot be used as it is; the message names the folder and the reason."""

    def __init__(self, folder: Path, reason: str):
        super().__init__(f"tile cache {folder}: {reason}", exit_code=2)
        self.reason = reason


@dataclass(frozen=True)
class Tile:
    file: str
    bounds: tuple[float, float, float, float]  # x0, z0, x1, z1 of its buildings' boxes (metres)
    buildings: int
    vertices: int
    bytes: int  # the file's size
    sha256: str

    @property
    def resident_bytes(self) -> int:
        """What the tile holds once loaded: its vertices (on the GPU, or on the CPU on the way there)."""
        return self.vertices * VERTEX_DTYPE.itemsize

    def distance(self, x: float, z: float) -> float:
        """Metres from (x, z) to the tile's bounds on the ground (0 inside)."""
        x0, z0, x1, z1 = self.bounds
        return float(np.hypot(max(x0 - x, 0.0, x - x1), max(z0 - z, 0.0, z - z1)))


@dataclass
class TileCache:
    """An opened (checked) cache: the city without its building vertices, and the tiles' list."""

    folder: Path
    tiles: list[Tile]
    city: City
    records: np.ndarray  # BUILDING_DTYPE, facades assigned
    boxes: np.ndarray  # render/_visibility.py's BOX_DTYPE, whole-city order; draw[:, 1] within the tile
    box_tile: np.ndarray  # the tile of each box
    facades: dict
    lod_faces: dict
    source: dict

    @property
    def total_bytes(self) -> int:
        return sum(t.resident_bytes for t in self.tiles)


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def source_identity(path: Path) -> dict:
    """The source file's name, size and SHA-256 (read in blocks)."""
    digest, size = hashlib.sha256(), 0
    with open(path, "rb") as handle:
        while block := handle.read(HASH_BLOCK):
            digest.update(block)
            size += len(block)
    return {"name": Path(path).name, "bytes": size, "sha256": digest.hexdigest()}


def _layouts() -> dict:
    """What must match for a cache to be read: its format, cityshade's version and the layouts."""
    from .. import __version__  # set after the package's imports, this module among them

    return {
        "format": FORMAT,
        "cityshade": __version__,
        "vertex": str(VERTEX_DTYPE.descr),
        "record": str(BUILDING_DTYPE.descr),
    }


def cut_tiles(buildings: CityBuildings, tile_size: float = TILE_SIZE):
    """(boxes with first vertices within their tile, tile of each box, per tile (vertices, bounds,
    buildings)). Each tile's vertices are its boxes' ranges in box order."""
    boxes = buildings.boxes()
    centre = 0.5 * (boxes["lo"][:, [0, 2]] + boxes["hi"][:, [0, 2]])
    cells = np.floor(centre / tile_size).astype(np.int64)
    if not len(boxes):
        return boxes, np.zeros(0, np.int64), []
    box_tile = np.unique(cells, axis=0, return_inverse=True)[1].ravel()
    order = np.lexsort((np.arange(len(boxes)), box_tile))  # by tile, then in box order
    count = boxes["draw"][order, 0].astype(np.int64)
    first = boxes["draw"][order, 1].astype(np.int64)
    before = np.cumsum(count) - count  # in the tiles' vertices, one after another
    tile_sorted = box_tile[order]
    tile_start = np.flatnonzero(np.r_[True, tile_sorted[1:] != tile_sorted[:-1]])
    local = before - before[tile_start][tile_sorted]
    vertices = buildings.vertices[np.repeat(first - before, count) + np.arange(count.sum())]
    cached = boxes.copy()
    cached["draw"][order, 1] = local
    ends = np.r_[before[tile_start][1:], count.sum()]
    lo = np.minimum.reduceat(boxes["lo"][order], tile_start)
    hi = np.maximum.reduceat(boxes["hi"][order], tile_start)
    tiles = []
    for k, start in enumerate(before[tile_start]):
        bounds = (float(lo[k, 0]), float(lo[k, 2]), float(hi[k, 0]), float(hi[k, 2]))
        buildings_in = int(np.diff(np.r_[tile_start, len(order)])[k])
        tiles.append((vertices[start : ends[k]], bounds, buildings_in))
    return cached, box_tile, tiles


def _is_cache(folder: Path) -> bool:
    return (folder / MANIFEST).is_file()


def write_tiles(city: City, folder: Path, source: dict | None = None, tile_size: float = TILE_SIZE) -> dict:
    """Meshes the city, cuts it into tiles and writes the cache folder whole (or leaves the old one);
    returns {"tiles", "buildings", "bytes", "seconds"}."""
    start = time.perf_counter()
    buildings = CityBuildings.of(city)
    boxes, box_tile, tiles = cut_tiles(buildings, tile_size)
    entries, written = [], 0
    with atomic_folder(folder, _is_cache) as tmp:
        (tmp / TILE_FOLDER).mkdir()
        for k, (vertices, bounds, count) in enumerate(tiles):
            stream = io.BytesIO()
            np.save(stream, vertices, allow_pickle=False)
            data = stream.getvalue()
            name = f"{TILE_FOLDER}/{k:05d}.npy"
            (tmp / name).write_bytes(data)
            entries.append(Tile(name, bounds, count, len(vertices), len(data), _sha256(data)))
            written += len(data)
        rest = {
            "city": city,
            "records": buildings.records,
            "boxes": boxes,
            "box_tile": box_tile,
            "facades": dict(buildings.facades),
            "lod_faces": buildings.lod_faces,
        }
        data = pickle.dumps(rest, protocol=pickle.HIGHEST_PROTOCOL)
        (tmp / CITY_FILE).write_bytes(data)
        written += len(data)
        manifest = {
            **_layouts(),
            "source": source,
            "tile_size": tile_size,
            "buildings": len(city.masses),
            "city": {"file": CITY_FILE, "bytes": len(data), "sha256": _sha256(data)},
            "tiles": [
                {
                    "file": t.file,
                    "bounds": t.bounds,
                    "buildings": t.buildings,
                    "vertices": t.vertices,
                    "bytes": t.bytes,
                    "resident_bytes": t.resident_bytes,
                    "sha256": t.sha256,
                }
                for t in entries
            ],
        }
        text = json.dumps(manifest, indent=1)
        (tmp / MANIFEST).write_text(text)
        written += len(text)
    return {
        "tiles": len(entries),
        "buildings": len(city.masses),
        "bytes": written,
        "seconds": time.perf_counter() - start,
    }


def _read_checked(folder: Path, name: str, size: int, sha256: str) -> bytes:
    path = folder / name
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise CacheProblem(folder, f"cannot read {name} ({exc.strerror or exc})") from None
    if len(data) != size:
        raise CacheProblem(folder, f"{name} is damaged ({len(data)} bytes, the manifest says {size})")
    if _sha256(data) != sha256:
        raise CacheProblem(folder, f"{name} is damaged (its SHA-256 is not the manifest's)")
    return data


def _manifest(folder: Path) -> dict:
    path = folder / MANIFEST
    if not folder.is_dir():
        raise CacheProblem(folder, "no such folder")
    try:
        manifest = json.loads(path.read_text())
    except FileNotFoundError:
        raise CacheProblem(folder, f"no {MANIFEST}") from None
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise CacheProblem(folder, f"{MANIFEST} is damaged ({type(exc).__name__})") from None
    if not isinstance(manifest, dict):
        raise CacheProblem(folder, f"{MANIFEST} is damaged (not an object)")
    return manifest


def open_tiles(folder: Path, source: dict | None = None) -> TileCache:
    """The checked cache in `folder`; with `source` (source_identity), made from that file."""
    folder = Path(folder)
    manifest = _manifest(folder)
    for key, wanted in _layouts().items():
        if manifest.get(key) != wanted:
            raise CacheProblem(folder, f"made with {key} {manifest.get(key)!r}, this cityshade needs {wanted!r}")
    if source is not None and manifest.get("source") != source:
        made = manifest.get("source") or {}
        raise CacheProblem(folder, f"made from another file ({made.get('name')!r}, {made.get('bytes')} bytes)")
    try:
        tiles = [
            Tile(
                str(t["file"]),
                tuple(float(v) for v in t["bounds"]),
                int(t["buildings"]),
                int(t["vertices"]),
                int(t["bytes"]),
                str(t["sha256"]),
            )
            for t in manifest["tiles"]
        ]
        city_entry = manifest["city"]
        data = _read_checked(folder, str(city_entry["file"]), int(city_entry["bytes"]), str(city_entry["sha256"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise CacheProblem(folder, f"{MANIFEST} is damaged (bad or missing {exc})") from None
    for tile in tiles:
        size = (folder / tile.file).stat().st_size if (folder / tile.file).is_file() else None
        if size != tile.bytes:
            raise CacheProblem(
                folder, f"{tile.file} is missing or damaged ({size} bytes, the manifest says {tile.bytes})"
            )
    try:
        rest = pickle.loads(data)  # checked against the manifest's SHA-256 first
    except Exception as exc:  # noqa: BLE001 - any unpickling failure means a damaged file
        raise CacheProblem(folder, f"{CITY_FILE} cannot be read ({type(exc).__name__})") from None
    return TileCache(
        folder,
        tiles,
        rest["city"],
        rest["records"],
        rest["boxes"],
        rest["box_tile"],
        rest["facades"],
        rest["lod_faces"],
        manifest.get("source"),
    )


def read_tile(cache: TileCache, index: int) -> np.ndarray:
    """Tile `index`'s vertices, checked against the manifest (size, SHA-256, layout)."""
    tile = cache.tiles[index]
    data = _read_checked(cache.folder, tile.file, tile.bytes, tile.sha256)
    try:
        vertices = np.load(io.BytesIO(data), allow_pickle=False)
    except ValueError as exc:
        raise CacheProblem(cache.folder, f"{tile.file} cannot be read ({exc})") from None
    if vertices.dtype != VERTEX_DTYPE or vertices.shape != (tile.vertices,):
        raise CacheProblem(cache.folder, f"{tile.file} holds {vertices.shape} {vertices.dtype}, not its tile")
    return vertices
