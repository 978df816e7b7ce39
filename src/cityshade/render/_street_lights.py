"""Street lamps as point lights with clustered (tiled) lighting: a 2D grid over the ground, each
cell listing the lamps whose reach touches it, in SSBOs that the ground and building shaders read
(shaders/city/street_lights.glsl). Hundreds of lamps cost each pixel only the few of its cell.

`light_grid` builds the lists (numpy, vectorised); `lamps_reaching_cell` is its brute-force twin.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..gl import binding, create_buffer, set_uniforms

CELL = 16.0  # metres per grid cell


@dataclass(frozen=True)
class LightGrid:
    origin: tuple[float, float]  # scene x, z of cell (0, 0)'s corner
    cells: tuple[int, int]  # nx, nz
    starts: np.ndarray  # uint32 (nx * nz + 1): lamps of cell c are indices[starts[c]:starts[c + 1]]
    indices: np.ndarray  # uint32 lamp indices, cell by cell (row-major: c = iz * nx + ix)

    def cell_of(self, x, z) -> np.ndarray:
        """Flat cell index of scene points, -1 outside the grid."""
        ix = np.floor((np.asarray(x, np.float32) - np.float32(self.origin[0])) / np.float32(CELL)).astype(int)
        iz = np.floor((np.asarray(z, np.float32) - np.float32(self.origin[1])) / np.float32(CELL)).astype(int)
        inside = (ix >= 0) & (ix < self.cells[0]) & (iz >= 0) & (iz < self.cells[1])
        return np.where(inside, iz * self.cells[0] + ix, -1)


def _distance_to_cells(lamps: np.ndarray, origin, ix: np.ndarray, iz: np.ndarray) -> np.ndarray:
    """Horizontal distance from each lamp to its cell rectangle (0 inside)."""
    x0 = origin[0] + ix * CELL
    z0 = origin[1] + iz * CELL
    dx = np.maximum(np.maximum(x0 - lamps[:, 0], lamps[:, 0] - (x0 + CELL)), 0.0)
    dz = np.maximum(np.maximum(z0 - lamps[:, 2], lamps[:, 2] - (z0 + CELL)), 0.0)
    return np.hypot(dx, dz)


def light_grid(lamps: np.ndarray) -> LightGrid:
    """The grid over lamps (N, 4: x, y, z, reach): each cell lists every lamp within reach of it."""
    lamps = np.asarray(lamps, np.float64).reshape(-1, 4)
    if not len(lamps):
        return LightGrid((0.0, 0.0), (0, 0), np.zeros(1, np.uint32), np.zeros(0, np.uint32))
    reach = lamps[:, 3]
    low = np.floor((lamps[:, [0, 2]] - reach[:, None]).min(axis=0) / CELL) * CELL
    high = (lamps[:, [0, 2]] + reach[:, None]).max(axis=0)
    nx, nz = (np.ceil((high - low) / CELL).astype(int) + 1).tolist()
    first = np.floor((lamps[:, [0, 2]] - reach[:, None] - low) / CELL).astype(int)
    last = np.floor((lamps[:, [0, 2]] + reach[:, None] - low) / CELL).astype(int)
    span = last - first + 1
    counts = span[:, 0] * span[:, 1]
    lamp = np.repeat(np.arange(len(lamps)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    ix = first[lamp, 0] + k % span[lamp, 0]
    iz = first[lamp, 1] + k // span[lamp, 0]
    near = _distance_to_cells(lamps[lamp], low, ix, iz) < reach[lamp]
    cell = (iz * nx + ix)[near]
    lamp = lamp[near]
    order = np.lexsort((lamp, cell))
    starts = np.zeros(nx * nz + 1, np.int64)
    np.add.at(starts, cell + 1, 1)
    return LightGrid(
        (float(low[0]), float(low[1])), (nx, nz), np.cumsum(starts).astype(np.uint32), lamp[order].astype(np.uint32)
    )


def lamps_reaching_cell(lamps: np.ndarray, grid: LightGrid, cell: int) -> np.ndarray:
    """Reference twin: indices of the lamps within reach of one cell, by testing every lamp."""
    lamps = np.asarray(lamps, np.float64).reshape(-1, 4)
    if cell < 0 or not len(lamps):
        return np.zeros(0, int)
    iz, ix = divmod(cell, grid.cells[0])
    distance = _distance_to_cells(lamps, grid.origin, np.full(len(lamps), ix), np.full(len(lamps), iz))
    return np.flatnonzero(distance < lamps[:, 3])


class StreetLightsGPU:
    """A city's lamps and their light grid in SSBOs (empty buffers for a city without lamps)."""

    def __init__(self, ctx: moderngl.Context, lamps: np.ndarray | None):
        lamps = np.zeros((0, 4), np.float32) if lamps is None else np.asarray(lamps, np.float32).reshape(-1, 4)
        self.count = len(lamps)
        self.grid = light_grid(lamps)
        self.buffers = [create_buffer(ctx, data) for data in (lamps, self.grid.starts, self.grid.indices)]

    def bind(self, program):
        for buffer, name in zip(self.buffers, ("StreetLamps", "LampCellStarts", "LampCellIndices")):
            buffer.bind_to_storage_buffer(binding(name))
        set_uniforms(
            program,
            u_lamp_origin=np.array(self.grid.origin, float),
            u_lamp_cells=self.grid.cells,
            u_lamp_cell_size=CELL,
        )

    def release(self):
        for buffer in self.buffers:
            buffer.release()
