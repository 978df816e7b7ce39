"""Streaming a tiled city (render/_tile_cache.py) under a memory budget (docs/scale.md, "Streaming").

`TileStreamer` decides, without any GL: each frame it takes the tiles nearest the camera, in order
of distance, as long as their bytes fit the budget; a resident tile no longer among them is
released; a wanted tile not yet resident is asked of a worker thread, which reads and checks its
file. Tiles the worker has read are handed over at the next `update` (UPLOAD_PER_UPDATE bytes a
frame at most), which never waits for the worker, so no frame waits on disk (`wait` is for a
single still, which waits for its view's tiles). Resident bytes, the tiles uploaded plus the tiles
being read, never exceed the budget: a read is asked for only when its tile fits beside them.

`StreamedCityGPU` is a CityGPU whose building vertex buffer is an arena of the budget's size (or
the whole city's, if smaller) with a slot per resident tile, which holds the tile's vertices, its
face rows and its ground triangles: the same buffer is the face table the vertex stage reads (a
tile's vertices point at their rows where its slot holds them) and the ground's vertex buffer
(drawn by a command per tile, after the ground no tile holds, which stays resident). The records
and the cull pass's boxes stay those of the whole city, in the whole city's order; a box's vertex
count is 0 while its tile is away and its first vertex points into its tile's slot while it is
resident. Every draw goes through draw commands (the cull pass's, or `resident_draws` for all
resident buildings), so the buildings that are resident are drawn exactly as the whole city would
draw them.
"""

from __future__ import annotations

import queue
import threading
from functools import partial
from typing import Callable

import moderngl
import numpy as np

from ..errors import CityshadeError, UsageError
from ..gl import create_buffer
from ..scene import FACE_DTYPE, GPU_VERTEX_DTYPE
from ._city_gpu import GROUND_ATTRIBUTES, GROUND_FORMAT, CityGPU
from ._tile_cache import GROUND_DTYPE, SLOT_UNIT, Tile, TileCache, face_offset, ground_offset, read_tile
from ._visibility import COMMAND_WORDS, BuildingVisibility

_STOP = -1
UPLOAD_PER_UPDATE = 32_000_000  # bytes of tiles uploaded per frame at most: no frame stalls on a burst of reads


def format_bytes(count: float) -> str:
    for unit in ("bytes", "KB", "MB", "GB"):
        if count < 1000 or unit == "GB":
            return f"{count:.0f} {unit}" if unit == "bytes" else f"{count:.1f} {unit}"
        count /= 1000
    raise AssertionError("unreachable")


def check_memory_budget(tiles: list[Tile], budget: int | None, eye):
    """Raises UsageError (one line) if the tile nearest the eye alone is over the budget."""
    if not tiles or budget is None:
        return
    x, z = float(eye[0]), float(eye[2])
    nearest = min(tiles, key=lambda tile: tile.distance(x, z))
    if nearest.resident_bytes > budget:
        raise UsageError(
            f"memory budget {format_bytes(budget)} is too small for the nearest tile "
            f"({nearest.file}: {format_bytes(nearest.resident_bytes)}, {nearest.buildings} buildings); "
            f"give --memory-budget {format_bytes(nearest.resident_bytes)} or more"
        )


class TileStreamer:
    """Which tiles are resident around the camera; `load(index, data)` and `release(index)` are
    called on the thread that calls `update` (the GL thread), `read(index)` (its data) on the worker."""

    def __init__(
        self,
        tiles: list[Tile],
        budget: int,
        read: Callable[[int], object],
        load: Callable[[int, object], None],
        release: Callable[[int], None],
    ):
        self.tiles, self.budget = tiles, budget
        self._read, self._load, self._release = read, load, release
        self.resident: dict[int, int] = {}  # tile -> bytes, uploaded
        self.reading: dict[int, int] = {}  # tile -> bytes, asked of the worker
        self.peak_bytes = 0
        self._bounds = np.array([t.bounds for t in tiles], np.float64).reshape(-1, 4)
        self._requests: queue.Queue[int] = queue.Queue()
        self._done: queue.Queue[tuple[int, object, BaseException | None]] = queue.Queue()
        self._worker = threading.Thread(target=self._work, name="tile reader", daemon=True)
        self._worker.start()

    @property
    def resident_bytes(self) -> int:
        return sum(self.resident.values()) + sum(self.reading.values())

    def _work(self):
        while (index := self._requests.get()) != _STOP:
            try:
                self._done.put((index, self._read(index), None))
            except BaseException as exc:  # noqa: BLE001 - handed to the GL thread, which reports it
                self._done.put((index, None, exc))

    def _by_distance(self, x: float, z: float) -> list[int]:
        """Tile indices, nearest (x, z) first (ties: lower index first); Tile.distance for all at once."""
        x0, z0, x1, z1 = self._bounds.T
        distance = np.hypot(
            np.maximum.reduce([x0 - x, np.zeros_like(x0), x - x1]),
            np.maximum.reduce([z0 - z, np.zeros_like(z0), z - z1]),
        )
        return np.argsort(distance, kind="stable").tolist()

    def wanted(self, x: float, z: float) -> list[int]:
        """The tiles nearest (x, z), nearest first, as many as fit the budget together."""
        chosen, total = [], 0
        for index in self._by_distance(x, z):
            total += self.tiles[index].resident_bytes
            if total > self.budget:
                break
            chosen.append(index)
        return chosen

    def _take(self, index: int, data: object, error: BaseException | None, wanted: set[int]) -> bool:
        del self.reading[index]
        if error is not None:
            if isinstance(error, CityshadeError):
                raise error
            raise CityshadeError(f"reading {self.tiles[index].file} failed: {error}", exit_code=2)
        if index not in wanted:  # the camera moved on while it was read
            return False
        self._load(index, data)
        self.resident[index] = self.tiles[index].resident_bytes
        return True

    def update(self, x: float, z: float) -> bool:
        """Releases the tiles no longer wanted, uploads the ones the worker has read, asks for the
        next ones; never waits. True if the resident tiles changed."""
        order = self.wanted(x, z)
        wanted = set(order)
        changed = False
        for index in [i for i in self.resident if i not in wanted]:
            self._release(index)
            del self.resident[index]
            changed = True
        uploaded = 0
        while uploaded < UPLOAD_PER_UPDATE:  # the rest waits in the queue for the next frames
            try:
                item = self._done.get_nowait()
            except queue.Empty:
                break
            changed |= self._take(*item, wanted)
            uploaded += self.tiles[item[0]].resident_bytes
        used = self.resident_bytes
        for index in order:
            size = self.tiles[index].resident_bytes
            if index not in self.resident and index not in self.reading and used + size <= self.budget:
                self.reading[index] = size
                self._requests.put(index)
                used += size
        self.peak_bytes = max(self.peak_bytes, self.resident_bytes)
        return changed

    def complete(self, x: float, z: float) -> bool:
        """Whether every tile wanted at (x, z) is resident."""
        return all(i in self.resident for i in self.wanted(x, z))

    def wait(self, x: float, z: float):
        """Updates until every tile wanted at (x, z) is resident (for a single still)."""
        order = self.wanted(x, z)
        wanted = set(order)
        self.update(x, z)
        while not all(i in self.resident for i in order):
            self._take(*self._done.get(), wanted)
            if any(i not in self.resident and i not in self.reading for i in order):
                self.update(x, z)  # room left by a read the camera no longer wants

    def close(self):
        """Stops the worker after the read in hand; the reads still asked for are dropped."""
        while True:
            try:
                self._requests.get_nowait()
            except queue.Empty:
                break
        self._requests.put(_STOP)
        self._worker.join()


class _Arena:
    """First-fit slots (in units of `unit` bytes) of a fixed buffer; `compact` moves every slot down
    to close the gaps (GPU copies), when a tile that fits the free space finds no gap wide enough,
    and tells `moved(key, old_first, new_first)` of each slot it moved."""

    def __init__(
        self, ctx: moderngl.Context, capacity: int, unit: int, moved: Callable[[int, int, int], None] | None = None
    ):
        self.ctx, self.capacity, self.unit, self._moved = ctx, capacity, unit, moved
        self.buffer = create_buffer(ctx, reserve=max(capacity, 1) * unit)
        self.slots: dict[int, tuple[int, int]] = {}  # key -> (first, count)

    def _gap(self, count: int) -> int | None:
        end = 0
        for first, used in sorted(self.slots.values()):
            if first - end >= count:
                return end
            end = first + used
        return end if self.capacity - end >= count else None

    def allocate(self, key: int, count: int) -> int:
        first = self._gap(count)
        if first is None:
            self.compact()
            first = self._gap(count)
            if first is None:
                raise RuntimeError(f"{count} units do not fit the arena's {self.capacity}")
        self.slots[key] = (first, count)
        return first

    def compact(self):
        size = self.unit
        end = 0
        for key, (first, count) in sorted(self.slots.items(), key=lambda item: item[1][0]):
            if first != end:  # through a scratch buffer: a copy within one buffer must not overlap
                scratch = create_buffer(self.ctx, reserve=count * size)
                self.ctx.copy_buffer(scratch, self.buffer, count * size, read_offset=first * size)
                self.ctx.copy_buffer(self.buffer, scratch, count * size, write_offset=end * size)
                scratch.release()
                self.slots[key] = (end, count)
                if self._moved is not None:
                    self._moved(key, first, end)
            end += count

    def free(self, key: int):
        del self.slots[key]


class StreamedCityGPU(CityGPU):
    """A CityGPU whose buildings come and go tile by tile (see the module's docstring)."""

    def __init__(
        self,
        ctx: moderngl.Context,
        cache: TileCache,
        budget: int | None = None,
        read: Callable[[int], np.ndarray] | None = None,
    ):
        self._upload_city(ctx, cache.city)
        self.facades, self._lod_faces = cache.facades, cache.lod_faces
        budget = cache.total_bytes if budget is None else int(budget)
        self.arena = _Arena(ctx, min(budget, cache.total_bytes) // SLOT_UNIT, SLOT_UNIT, self._rebase_faces)
        self.building_vbo = self.faces = self.arena.buffer  # vertices, face rows and ground, a slot per tile
        self.building_indices = None  # a tile's slot holds its triangle list as meshed
        self.building_vertex_count = 0  # resident
        self._count = cache.boxes["draw"][:, 0].copy()
        self._local_first = cache.boxes["draw"][:, 1].copy()
        order = np.argsort(cache.box_tile, kind="stable")
        self._tile_boxes = np.split(order, np.cumsum(np.bincount(cache.box_tile, minlength=len(cache.tiles)))[:-1])
        self.boxes = cache.boxes.copy()  # their draw fields follow the tiles resident, uploaded when they change
        self.boxes["draw"][:, 0] = 0
        self.visibility = BuildingVisibility(ctx, self.boxes)
        self.resident_draws = create_buffer(ctx, reserve=max(len(self.boxes), 1) * COMMAND_WORDS * 4)
        self._ground_draws = np.zeros((len(cache.tiles), COMMAND_WORDS), np.uint32)  # a command per tile, in tile order
        self._ground_draws[:, 1] = 1
        self.ground_draws = create_buffer(ctx, self._ground_draws)  # none resident yet
        self._upload_records(cache.records.copy())
        self.streamer = TileStreamer(
            cache.tiles, budget, read or partial(read_tile, cache), self._load_tile, self._release_tile
        )

    def _first_vertex(self, index: int) -> int:
        return self.arena.slots[index][0] * SLOT_UNIT // GPU_VERTEX_DTYPE.itemsize

    def _ground_first(self, index: int) -> int:
        tile = self.streamer.tiles[index]
        return (
            self.arena.slots[index][0] * SLOT_UNIT + ground_offset(tile.vertices, tile.faces)
        ) // GROUND_DTYPE.itemsize

    def _load_tile(self, index: int, data: tuple[np.ndarray, np.ndarray, np.ndarray]):
        vertices, faces, ground = data
        start = self.arena.allocate(index, self.streamer.tiles[index].resident_bytes // SLOT_UNIT) * SLOT_UNIT
        rows = start + face_offset(len(vertices))
        vertices["face"] += np.uint32(rows // FACE_DTYPE.itemsize)  # the tile's rows where its slot holds them
        self.building_vbo.write(vertices.tobytes(), offset=start)
        self.building_vbo.write(faces.tobytes(), offset=rows)
        self.building_vbo.write(ground.tobytes(), offset=start + ground_offset(len(vertices), len(faces)))
        self._ground_draws[index, 0] = len(ground)
        boxes = self._tile_boxes[index]
        draw = self.boxes["draw"]
        draw[boxes, 0] = self._count[boxes]
        draw[boxes, 1] = self._first_vertex(index) + self._local_first[boxes]
        self.building_vertex_count += len(vertices)

    def _rebase_faces(self, index: int, old_first: int, new_first: int):
        """A slot the arena moved: its vertices point at their face rows where the slot is now."""
        size, offset = self.streamer.tiles[index].vertices * GPU_VERTEX_DTYPE.itemsize, new_first * SLOT_UNIT
        held = np.frombuffer(self.building_vbo.read(size=size, offset=offset), GPU_VERTEX_DTYPE).copy()
        held["face"] -= np.uint32((old_first - new_first) * SLOT_UNIT // FACE_DTYPE.itemsize)  # slots only move down
        self.building_vbo.write(held.tobytes(), offset=offset)

    def _release_tile(self, index: int):
        self.building_vertex_count -= self.streamer.tiles[index].vertices
        self.arena.free(index)
        draw = self.boxes["draw"]
        draw[self._tile_boxes[index], 0] = 0
        self._ground_draws[index, 0] = 0

    def _moved_boxes(self):
        """The boxes' and the ground's draws after the arena compacted: each resident tile's slot start."""
        draw = self.boxes["draw"]
        for index in self.arena.slots:
            draw[self._tile_boxes[index], 1] = self._first_vertex(index) + self._local_first[self._tile_boxes[index]]
            self._ground_draws[index, 2] = self._ground_first(index)

    def _upload_boxes(self):
        self.ground_draws.write(self._ground_draws.tobytes())
        boxes = self.boxes
        self.visibility.upload_draws(boxes)
        commands = np.zeros((len(boxes), COMMAND_WORDS), np.uint32)
        commands[:, 0], commands[:, 2] = boxes["draw"][:, 0], boxes["draw"][:, 1]
        commands[:, 1] = commands[:, 0] > 0
        self.resident_draws.write(commands.tobytes())

    def follow(self, eye) -> bool:
        """Streams toward the camera at `eye` without waiting (once per frame); True if tiles came or went."""
        changed = self.streamer.update(float(eye[0]), float(eye[2]))
        if changed:
            self._moved_boxes()
            self._upload_boxes()
        return changed

    def wait(self, eye):
        """Loads every tile the camera at `eye` wants before returning (for a single still)."""
        check_memory_budget(self.streamer.tiles, self.streamer.budget, eye)
        self.streamer.wait(float(eye[0]), float(eye[2]))
        self._moved_boxes()
        self._upload_boxes()

    def drawn_buildings(self) -> np.ndarray:
        """Per building, whether its tile is resident."""
        drawn = np.zeros(max(self.building_count, 1), bool)
        drawn[self.boxes["draw"][:, 2]] = self.boxes["draw"][:, 0] > 0
        return drawn

    def draw_buildings(self, program, view_projection: np.ndarray | None = None, draws: moderngl.Buffer | None = None):
        """As CityGPU's, always through draw commands: the arena's free slots hold stale vertices."""
        if draws is None:
            draws = self.resident_draws if view_projection is None else self.visibility.frustum(view_projection)
        super().draw_buildings(program, draws=draws)

    def draw_ground(self, program):
        """The ground no tile holds, then each resident tile's, in tile order."""
        super().draw_ground(program)
        if self.streamer.tiles:
            vao = self._vao(program, self.arena.buffer, GROUND_FORMAT, GROUND_ATTRIBUTES)
            vao.render_indirect(self.ground_draws, moderngl.TRIANGLES, count=len(self.streamer.tiles))

    def release(self):
        self.streamer.close()
        self.resident_draws.release()
        self.ground_draws.release()
        super().release()
