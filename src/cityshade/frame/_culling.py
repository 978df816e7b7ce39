"""The batched city's vertex order and its CPU frustum culling: buildings are grouped into square
chunks, each a contiguous vertex range with a bounding box (and each building a contiguous range
within it, which the GPU culling of render/_visibility.py draws from)."""

from __future__ import annotations

import numpy as np

CHUNK_SIZE = 96.0  # metres: a city block or so


def frustum_planes(view_projection: np.ndarray) -> np.ndarray:
    """The six clip planes (a, b, c, d), inside where a*x + b*y + c*z + d >= 0 (Gribb & Hartmann)."""
    m = view_projection
    planes = np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]])
    return planes / np.linalg.norm(planes[:, :3], axis=1, keepdims=True)


def boxes_visible(planes: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Conservative test of boxes (N, 3) against the planes: False only when a box is entirely
    outside one plane."""
    # the box corner farthest along each plane's normal
    corner = np.where(planes[None, :, :3] >= 0, hi[:, None, :], lo[:, None, :])
    distance = np.sum(corner * planes[None, :, :3], axis=-1) + planes[None, :, 3]
    return np.all(distance >= 0, axis=1)


def building_cells(vertices: np.ndarray, chunk_size: float = CHUNK_SIZE) -> np.ndarray:
    """(buildings, 2) int64: the chunk (x, z cell) of each building, by the mean of its vertices."""
    building = vertices["ids"][:, 0]
    count = int(building.max()) + 1 if len(building) else 0
    centre = np.zeros((count, 2))
    np.add.at(centre, building, vertices["position"][:, [0, 2]].astype(np.float64))
    centre /= np.maximum(np.bincount(building, minlength=count), 1)[:, None]
    return np.floor(centre / chunk_size).astype(np.int64)


def chunk_vertices(vertices: np.ndarray, chunk_size: float = CHUNK_SIZE) -> tuple[np.ndarray, "BuildingChunks"]:
    """A building vertex array reordered chunk by chunk, and the chunks' ranges and boxes (the
    reordered vertices are the caller's: once uploaded, no copy needs to stay)."""
    building = vertices["ids"][:, 0]
    positions = vertices["position"].astype(np.float64)
    cell = building_cells(vertices, chunk_size)
    count = len(cell)
    keys = np.unique(cell, axis=0, return_inverse=True)[1].ravel() if count else np.zeros(0, np.int64)
    # by chunk, then building (each building one contiguous range for the cull pass); stable, so
    # triangles stay whole and a building's vertices stay in order
    order = np.lexsort((building, keys[building]))
    vertex_chunk = keys[building][order]
    chunks = int(vertex_chunk.max()) + 1 if len(vertex_chunk) else 0
    lo = np.full((chunks, 3), np.inf)
    hi = np.full((chunks, 3), -np.inf)
    sorted_pos = positions[order]
    np.minimum.at(lo, vertex_chunk, sorted_pos)
    np.maximum.at(hi, vertex_chunk, sorted_pos)
    first = np.searchsorted(vertex_chunk, np.arange(chunks)).astype(np.uint32)
    return vertices[order], BuildingChunks(first, np.bincount(vertex_chunk, minlength=chunks).astype(np.uint32), lo, hi)


class BuildingChunks:
    """The chunks of a vertex array ordered by chunk_vertices: each chunk's vertex range and box."""

    def __init__(self, first: np.ndarray, count: np.ndarray, lo: np.ndarray, hi: np.ndarray):
        self.first, self.count, self.lo, self.hi = first, count, lo, hi

    def __len__(self) -> int:
        return len(self.first)

    def visible(self, view_projection: np.ndarray) -> np.ndarray:
        return boxes_visible(frustum_planes(view_projection), self.lo, self.hi)

    def visible_runs(self, keep: np.ndarray) -> list[tuple[int, int]]:
        """(first vertex, vertex count) of the chunks where `keep` is set, neighbours merged into one run."""
        runs: list[tuple[int, int]] = []
        for first, count in zip(self.first[keep].tolist(), self.count[keep].tolist()):
            if runs and runs[-1][0] + runs[-1][1] == first:
                runs[-1] = (runs[-1][0], runs[-1][1] + count)
            else:
                runs.append((first, count))
        return runs
