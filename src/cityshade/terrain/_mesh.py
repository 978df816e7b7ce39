"""The terrain as triangles: the grid cut into square chunks, each drawn at a level of detail that
coarsens with its distance from the map's data (level L keeps every 2**L-th sample), cracks between
chunks of different levels (and the grid's outer edge) closed by skirts hanging below the edge.

At level 0 the triangles are the very ones `Terrain.height_at` interpolates (terrain/_grid.py: two
per cell, split from the north-east to the south-west corner), so whatever is placed with it over
the data stands on the drawn ground.
"""

from __future__ import annotations

import numpy as np

from ._grid import Terrain

CHUNK = 32  # cells a side of a chunk at level 0 (a power of two: every level divides it)
MAX_LEVEL = 4  # chunks at most 16 times coarser
SKIRT_MARGIN = 1.0  # metres a skirt reaches below the lowest edge of the chunk it hangs from


def _levels(terrain: Terrain, focus, chunks: tuple[int, int]) -> np.ndarray:
    """Each chunk's level: 0 over `focus` (west, south, east, north map metres), one more per ring
    of chunks around it, at most MAX_LEVEL."""
    west, south, east, north = focus
    side = CHUNK * terrain.spacing
    first_col = np.floor((west - terrain.west) / side)
    last_col = np.floor((east - terrain.west) / side)
    first_row = np.floor((terrain.north - north) / side)
    last_row = np.floor((terrain.north - south) / side)
    rows, cols = np.meshgrid(np.arange(chunks[0]), np.arange(chunks[1]), indexing="ij")
    away_col = np.maximum(np.maximum(first_col - cols, cols - last_col), 0)
    away_row = np.maximum(np.maximum(first_row - rows, rows - last_row), 0)
    return np.minimum(np.maximum(away_col, away_row), MAX_LEVEL).astype(np.int64)


def _samples(start: int, end: int, step: int) -> np.ndarray:
    """Sample indices from start to end (both kept) every `step`."""
    return np.unique(np.r_[np.arange(start, end, step), end])


def _map_points(terrain: Terrain, rows, cols) -> np.ndarray:
    """(..., 3) map (east, north, height) of grid samples."""
    return np.stack(
        np.broadcast_arrays(
            terrain.west + cols * terrain.spacing, terrain.north - rows * terrain.spacing, terrain.heights[rows, cols]
        ),
        axis=-1,
    ).astype(np.float64)


def _chunk_triangles(terrain: Terrain, r: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(K*3, 3) map points of the cells between sample rows `r` and columns `c`."""
    rr, cc = np.meshgrid(r, c, indexing="ij")
    p = _map_points(terrain, rr, cc)
    a, b, cw, d = p[:-1, :-1], p[:-1, 1:], p[1:, :-1], p[1:, 1:]  # north-west, north-east, south-west, south-east
    return np.stack([a, cw, b, b, cw, d], axis=2).reshape(-1, 3)  # counter-clockwise seen from above


def _skirt(edge: np.ndarray, bottom: float) -> np.ndarray:
    """(K*3, 3) map points of a vertical strip from an edge's points (n, 3) down to `bottom`."""
    low = edge.copy()
    low[:, 2] = bottom
    a, b, c, d = edge[:-1], edge[1:], low[:-1], low[1:]
    return np.stack([a, c, b, b, c, d], axis=1).reshape(-1, 3)


def terrain_mesh(terrain: Terrain, focus: tuple[float, float, float, float]) -> np.ndarray:
    """(N*3, 3) float64 map points (east, north, height) of the terrain's triangles, chunk by chunk,
    finest over `focus` (map metres), with skirts where a chunk meets a coarser one or the grid ends."""
    rows, cols = terrain.shape
    chunks = (-(-(rows - 1) // CHUNK), -(-(cols - 1) // CHUNK))
    levels = _levels(terrain, focus, chunks)
    pieces = []
    for i in range(chunks[0]):
        for j in range(chunks[1]):
            step = 1 << int(levels[i, j])
            r0, r1 = i * CHUNK, min((i + 1) * CHUNK, rows - 1)
            c0, c1 = j * CHUNK, min((j + 1) * CHUNK, cols - 1)
            r, c = _samples(r0, r1, step), _samples(c0, c1, step)
            pieces.append(_chunk_triangles(terrain, r, c))
            bottom = float(terrain.heights[r0 : r1 + 1, c0 : c1 + 1].min()) - SKIRT_MARGIN
            edges = {
                (i - 1, j): _map_points(terrain, r0, c),
                (i + 1, j): _map_points(terrain, r1, c),
                (i, j - 1): _map_points(terrain, r, c0),
                (i, j + 1): _map_points(terrain, r, c1),
            }
            for (ni, nj), edge in edges.items():
                inside = 0 <= ni < chunks[0] and 0 <= nj < chunks[1]
                if not inside or levels[ni, nj] != levels[i, j]:
                    pieces.append(_skirt(edge, bottom))
    return np.concatenate(pieces)
