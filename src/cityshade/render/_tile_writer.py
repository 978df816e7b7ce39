"""Writing a tile cache (the layout is render/_tile_cache.py's): the city cut into tiles, each tile
meshed on its own by `mesh_tile` (a plain function of its masses, so that any process can run it:
`write_tiles(..., run=...)` hands the tiles to Ray tasks in `cityshade tile --workers K`), and one
writer, this process, for every file of the cache.

A build is resumable. Each tile meshed is kept at once in a work folder beside the cache,
`.NAME.partial/`: its .npz, then its piece (boxes, records, facades, far-colour faces, counts), the
piece last and each file whole (written under a temporary name and renamed), so a killed build
leaves whole tiles only. The folder's `plan.json` names what the tiles are made of (the cache
layouts and meshing code, the source file, the tile size, and a hash of every building's
placement); a build of the same plan keeps the tiles found there and meshes the rest, a build of
another plan starts afresh. When every tile is there, the cache folder is written whole from them
(the .npz files are moved, not copied) and the work folder removed. The tiles, their names and
their bytes do not depend on how many workers meshed them nor in which order they finished.
"""

from __future__ import annotations

import functools
import hashlib
import io
import itertools
import json
import os
import pickle
import shutil
import time
import warnings
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator

import numpy as np

from .._files import atomic_folder, check_replaceable_folder
from ..errors import UsageError
from ..frame import building_cells
from ..scene import BUILDING_DTYPE, GROUND_LAND, City, face_table, placements
from ._building_lod import SAMPLE_FACE_DTYPE
from ._city_gpu import CityBuildings, ground_vertices
from ._facades import NARROW_FACES, GrammarFitWarning
from ._tile_cache import (
    CITY_FILE,
    KIND,
    MANIFEST,
    TILE_FOLDER,
    TILE_SIZE,
    Tile,
    _CityUnpickler,
    _layouts,
    _sha256,
)
from ._visibility import BOX_DTYPE

PARTIAL = ".{}.partial"  # the work folder of a build of the cache NAME, beside it
PLAN = "plan.json"
PIECES = "pieces"

# A runner takes the per-tile function, the arguments every call shares and jobs (key, *arguments),
# and yields (key, function(*shared, *arguments)) for every job, in any order.
Runner = Callable[[Callable, tuple, Iterable[tuple]], Iterator[tuple]]


def run_here(function: Callable, shared: tuple, jobs: Iterable[tuple]) -> Iterator[tuple]:
    """One job after another, in this process."""
    for key, *arguments in jobs:
        yield key, function(*shared, *arguments)


def on_ray(workers: int) -> Runner:
    """A runner of Ray tasks, `workers` at once, on the Ray runtime this process is connected to."""
    return functools.partial(_on_ray, workers)


def _on_ray(workers: int, function, shared: tuple, jobs):
    """Yields (key, function(*shared, *arguments)) for jobs (key, *arguments) run as Ray tasks, 2
    per worker queued at most (the driver holds no more of the tiles' masses than that); `shared`
    (the whole city's placements) is put in Ray's object store once. A task whose worker dies is
    retried."""
    import ray

    task = ray.remote(num_cpus=1, max_retries=3)(function)
    shared = [ray.put(value) for value in shared]
    pending: dict = {}
    jobs = iter(jobs)
    while True:
        for key, *arguments in itertools.islice(jobs, max(0, 2 * workers - len(pending))):
            pending[task.remote(*shared, *arguments)] = key
        if not pending:
            return
        ready, _ = ray.wait(list(pending), num_returns=1)
        yield pending.pop(ready[0]), ray.get(ready[0])


@dataclass
class TilePiece:
    """One tile as `mesh_tile` makes it: its .npz bytes (None when it draws nothing) and what the
    cache's city file and manifest need of it."""

    data: bytes | None
    counts: tuple[int, int, int, int]  # buildings (boxes), vertices, face rows, ground vertices
    bounds: tuple[float, float, float, float] | None
    boxes: np.ndarray  # BOX_DTYPE, first vertex within the tile
    cells: np.ndarray  # chunk cell per box
    records: np.ndarray  # BUILDING_DTYPE of the tile's buildings, in `index` order
    facades: dict
    lod_faces: np.ndarray  # SAMPLE_FACE_DTYPE, buildings numbered in the whole city


def _split(cell: np.ndarray, cells: int) -> list[np.ndarray]:
    """The indices of `cell` in each of `cells` cells, ascending."""
    order = np.argsort(cell, kind="stable")
    return np.split(order, np.cumsum(np.bincount(cell, minlength=cells))[:-1])


def _groups(masses: list, ground: np.ndarray, tile_size: float) -> tuple[list, list]:
    """Per tile (square cells with buildings, in (x, z) order): the buildings whose masses stand in
    it and the ground triangles whose centres lie in it, of those no wider than a tile. No tile
    holds the ground of cells without buildings, the wider triangles, nor the land under a map
    (GROUND_LAND, reaching the horizon): a tile away must not leave a hole down to the sky below
    the horizon."""
    position = np.array([m.position for m in masses], np.float64).reshape(-1, 2)
    corners = ground.reshape(-1, 3, 4)[:, :, [0, 2]].astype(np.float64)
    small = np.all(np.ptp(corners, axis=1) <= tile_size, axis=1) & (ground.reshape(-1, 3, 4)[:, 0, 3] != GROUND_LAND)
    keys = np.floor(np.concatenate([position, corners[small].mean(axis=1)]) / tile_size).astype(np.int64)
    cells, cell = np.unique(keys.reshape(-1, 2), axis=0, return_inverse=True)
    cell = cell.ravel()
    built = np.flatnonzero(np.bincount(cell[: len(position)], minlength=len(cells)))
    triangles = np.flatnonzero(small)
    buildings = _split(cell[: len(position)], len(cells))
    tile_ground = _split(cell[len(position) :], len(cells))
    return [buildings[k] for k in built], [triangles[tile_ground[k]] for k in built]


def _mesh(masses: list, index: np.ndarray):
    """Meshes `masses` (those of the whole city's buildings `index`): (vertices, boxes, chunk cell
    per box, CityBuildings with local indices). Boxes are in the whole city's order (chunk cell,
    then building), their first vertex counted within the tile; vertices and boxes carry the
    buildings' indices in the whole city."""
    meshed = CityBuildings.of(masses)
    boxes = meshed.boxes()
    local = boxes["draw"][:, 2].astype(np.int64)
    cells = building_cells(meshed.vertices)[local]
    order = np.lexsort((index[local], cells[:, 1], cells[:, 0]))
    boxes, cells, local = boxes[order], cells[order], local[order]
    count, first = boxes["draw"][:, 0].astype(np.int64), boxes["draw"][:, 1].astype(np.int64)
    before = np.cumsum(count) - count
    vertices = meshed.vertices[np.repeat(first - before, count) + np.arange(count.sum())]
    vertices["ids"][:, 0] = index[vertices["ids"][:, 0]]
    boxes["draw"][:, 1], boxes["draw"][:, 2] = before, index[local]
    return vertices, boxes, cells, meshed


def _bounds(boxes: np.ndarray, ground: np.ndarray) -> tuple[float, float, float, float]:
    """x0, z0, x1, z1 of the buildings' boxes and the ground triangles' corners."""
    x = np.r_[boxes["lo"][:, 0], boxes["hi"][:, 0], ground[:, 0]]
    z = np.r_[boxes["lo"][:, 2], boxes["hi"][:, 2], ground[:, 2]]
    return float(x.min()), float(z.min()), float(x.max()), float(z.max())


def mesh_tile(placement: np.ndarray, masses: list, index: np.ndarray, ground: np.ndarray) -> TilePiece:
    """One tile: `masses`, the whole city's buildings `index`, meshed as CityGPU meshes the whole
    city; `placement`, the whole city's PLACEMENT_DTYPE rows; `ground`, the tile's ground vertices.
    A function of its arguments only: the same tile gives the same bytes in any process."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GrammarFitWarning)  # counted in `facades`, one warning for the city
        vertices, boxes, cells, meshed = _mesh(masses, index)
    lod_faces = meshed.lod_faces.copy()
    lod_faces["building"] = index[lod_faces["building"]]  # the tile's building -> the city's
    piece = TilePiece(None, (0, 0, 0, 0), None, boxes, cells, meshed.records, dict(meshed.facades), lod_faces)
    if len(boxes):
        vertices, faces = face_table(vertices, placement)
        stream = io.BytesIO()
        np.savez(stream, vertices=vertices, faces=faces, ground=ground)
        piece.data = stream.getvalue()
        piece.counts = len(boxes), len(vertices), len(faces), len(ground)
        piece.bounds = _bounds(boxes, ground)
    return piece


def check_cache_folder(folder: Path):
    """Fails with one line before any work if `folder` cannot take a cache (it holds something else)."""
    check_replaceable_folder(folder, KIND)


def _write_whole(path: Path, data: bytes):
    """`data` under a temporary name, then renamed: a kill leaves the file whole or absent."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


class _Pieces:
    """The work folder of a build: the tiles meshed so far, by group number."""

    def __init__(self, folder: Path, plan: dict):
        self.folder = folder.parent / PARTIAL.format(folder.name)
        if self.folder.exists() and not (self.folder / PLAN).is_file():  # never remove what a build did not make
            raise UsageError(f"{self.folder} is in the way of the build's work folder; move it away or remove it")
        try:
            kept = json.loads((self.folder / PLAN).read_text()) == plan
        except (OSError, ValueError):
            kept = False
        if not kept:
            shutil.rmtree(self.folder, ignore_errors=True)
            (self.folder / PIECES).mkdir(parents=True)
            _write_whole(self.folder / PLAN, json.dumps(plan).encode())
        self.done = {int(p.stem) for p in (self.folder / PIECES).glob("*.pickle")}

    def _paths(self, group: int) -> tuple[Path, Path]:
        return self.folder / PIECES / f"{group:09d}.npz", self.folder / PIECES / f"{group:09d}.pickle"

    def put(self, group: int, piece: TilePiece):
        tile, meta = self._paths(group)
        if piece.data is not None:
            _write_whole(tile, piece.data)
        piece.data = None if piece.data is None else _sha256(piece.data)  # the file holds the bytes
        _write_whole(meta, pickle.dumps(piece, protocol=pickle.HIGHEST_PROTOCOL))
        self.done.add(group)

    def get(self, group: int) -> tuple[TilePiece, Path | None]:
        """The piece (its `data` the .npz's SHA-256) and the .npz (None when it draws nothing), or
        KeyError when either is missing or damaged: that tile is meshed again."""
        tile, meta = self._paths(group)
        try:
            piece = _CityUnpickler(io.BytesIO(meta.read_bytes())).load()
            if not isinstance(piece, TilePiece):
                raise ValueError(meta)
            if piece.data is not None and _sha256(tile.read_bytes()) != piece.data:
                raise ValueError(tile)
        except Exception:  # noqa: BLE001 - anything unreadable is meshed again
            self.done.discard(group)
            raise KeyError(group) from None
        return piece, tile if piece.data is not None else None

    def remove(self):
        shutil.rmtree(self.folder, ignore_errors=True)


def _plan(masses: list, placement: np.ndarray, source: dict | None, tile_size: float, groups: int) -> dict:
    return {
        **_layouts(),
        "source": source,
        "tile_size": tile_size,
        "buildings": len(masses),
        "groups": groups,
        "placements": hashlib.sha256(placement.tobytes()).hexdigest(),
    }


def write_tiles(
    city: City,
    folder: Path,
    source: dict | None = None,
    tile_size: float = TILE_SIZE,
    run: Runner = run_here,
    progress: Callable[[int, int], None] | None = None,
) -> dict:
    """Meshes the city tile by tile through `run` (run_here: in this process, one tile at a time)
    and writes the cache folder whole (or leaves the old one), resuming the tiles an interrupted
    build of the same plan kept; `progress(done, total)` after each tile. Returns {"tiles",
    "buildings", "bytes", "seconds", "resumed"} (resumed: tiles kept from an earlier build)."""
    start = time.perf_counter()
    folder = Path(folder)
    check_cache_folder(folder)
    masses = list(city.masses)  # mass objects while meshing: the city keeps columns
    placement = placements(masses)
    ground = ground_vertices(city).reshape(-1, 3, 4)
    groups = list(zip(*_groups(masses, ground, tile_size)))
    pieces = _Pieces(folder, _plan(masses, placement, source, tile_size, len(groups)))
    resumed = len(pieces.done)
    jobs = (
        (g, [masses[i] for i in index], index, ground[triangles].reshape(-1, 4))
        for g, (index, triangles) in enumerate(groups)
        if g not in pieces.done
    )
    for group, piece in run(mesh_tile, (placement,), jobs):
        pieces.put(group, piece)
        if progress is not None:
            progress(len(pieces.done), len(groups))
    summary = _assemble(city, folder, source, tile_size, masses, placement, groups, pieces, ground)
    pieces.remove()
    return {**summary, "seconds": time.perf_counter() - start, "resumed": resumed}


def _assemble(city, folder, source, tile_size, masses, placement, groups, pieces: _Pieces, ground) -> dict:
    """The cache folder, whole, from the pieces in group order (a damaged piece is meshed again here)."""
    records = np.zeros(len(masses), BUILDING_DTYPE)
    facades, lod_faces, tiles, boxes, cells, box_tile = Counter(), [], [], [], [], []
    resident = np.ones(len(ground), bool)  # the ground no tile holds
    with atomic_folder(folder, KIND) as tmp:
        (tmp / TILE_FOLDER).mkdir()
        for g, (index, triangles) in enumerate(groups):
            try:
                piece, path = pieces.get(g)
            except KeyError:
                pieces.put(g, mesh_tile(placement, [masses[i] for i in index], index, ground[triangles].reshape(-1, 4)))
                piece, path = pieces.get(g)
            records[index] = piece.records
            facades.update(piece.facades)
            lod_faces.append(piece.lod_faces)
            if path is None:
                continue
            resident[triangles] = False
            name = f"{TILE_FOLDER}/{len(tiles):05d}.npz"
            os.replace(path, tmp / name)
            box_tile.append(np.full(len(piece.boxes), len(tiles)))
            tiles.append(Tile(name, piece.bounds, *piece.counts, (tmp / name).stat().st_size, piece.data))
            boxes.append(piece.boxes)
            cells.append(piece.cells)
        # the layouts' own dtypes, not the pieces' unpickled copies of them: the same pickle either way
        boxes = np.concatenate(boxes).view(BOX_DTYPE) if boxes else np.zeros(0, BOX_DTYPE)
        cells = np.concatenate(cells) if cells else np.zeros((0, 2), np.int64)
        order = np.lexsort((boxes["draw"][:, 2], cells[:, 1], cells[:, 0]))  # as CityGPU orders them
        rest = {
            "city": city.keep_ground(np.repeat(resident, 3)),  # the tiles hold the rest
            "records": records,
            "boxes": boxes[order],
            "box_tile": np.concatenate(box_tile)[order] if box_tile else np.zeros(0, np.int64),
            "facades": dict(facades),
            "lod_faces": _by_building(lod_faces),
        }
        data = _stable_pickle(rest)
        (tmp / CITY_FILE).write_bytes(data)
        manifest = {
            **_layouts(),
            "source": source,
            "tile_size": tile_size,
            "buildings": len(masses),
            "city": {"file": CITY_FILE, "bytes": len(data), "sha256": _sha256(data)},
            "tiles": [{**asdict(t), "resident_bytes": t.resident_bytes} for t in tiles],
        }
        text = json.dumps(manifest, indent=1)
        (tmp / MANIFEST).write_text(text)
    if facades.get(NARROW_FACES):
        warnings.warn(
            f"{facades[NARROW_FACES]} wall faces are narrower than their building's grammar fits: drawn as plain walls",
            GrammarFitWarning,
            stacklevel=3,
        )
    written = sum(t.bytes for t in tiles) + len(data) + len(text)
    return {"tiles": len(tiles), "buildings": len(masses), "bytes": written}


class _StablePickler(pickle._Pickler):  # the Python pickler: the C one writes sets without asking
    """Sets and frozensets pickled in sorted order: their own order follows the strings' hashes,
    which differ from process to process, and a cache is the same bytes whoever writes it."""

    dispatch = dict(pickle._Pickler.dispatch)

    def _save_sorted(self, obj):
        try:
            items = sorted(obj)
        except TypeError:  # items without an order: as they come
            items = list(obj)
        self.save_reduce(type(obj), (items,), obj=obj)

    dispatch[set] = dispatch[frozenset] = _save_sorted


def _stable_pickle(value) -> bytes:
    stream = io.BytesIO()
    _StablePickler(stream, protocol=4).dump(value)  # 5 sends arrays as buffers, which the Python pickler mishandles
    return stream.getvalue()


def _by_building(faces: list[np.ndarray]) -> np.ndarray:
    """The tiles' sample faces as one array in building order, as grammar_sample_faces makes it."""
    if not faces:
        return np.zeros(0, SAMPLE_FACE_DTYPE)
    faces = np.concatenate(faces).view(SAMPLE_FACE_DTYPE)
    return faces[np.argsort(faces["building"], kind="stable")]
