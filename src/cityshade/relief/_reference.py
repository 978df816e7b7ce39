"""The numpy reference ray tracer: the exact first hit of each ray with a facade's relief.

It works in map space (x in texels along the facade, y in texels up, z in depth steps into the
wall), where facade rays stay straight. The relief is the union of solid columns, one per
texel, from the texel's depth down to below the deepest texel. Texels are first merged into
the cells of the grid of repeated rows and columns (same solid, fewer boxes); then every ray is
tested against every cell by brute force and keeps the nearest hit. A side face takes the
material of the column it bounds, the higher surface (paper fig. 3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._maps import DetailMaps

# Hit faces by outward normal in map space; the shaders use the same numbers (trace.glsl).
FACE_FRONT, FACE_NEG_X, FACE_POS_X, FACE_NEG_Y, FACE_POS_Y = range(5)
RELIEF_FACE_CODES = {
    "FACE_FRONT": FACE_FRONT,
    "FACE_NEG_X": FACE_NEG_X,
    "FACE_POS_X": FACE_POS_X,
    "FACE_NEG_Y": FACE_NEG_Y,
    "FACE_POS_Y": FACE_POS_Y,
}  # the shaders' FACE_* of relief
MISS = -1


@dataclass(frozen=True)
class Hits:
    material: np.ndarray  # (H, W) int, MISS where the ray misses the facade
    face: np.ndarray  # (H, W) int face id, MISS where it misses
    point: np.ndarray  # (H, W, 3) hit point in map space (nan on a miss)


def _cells(maps: DetailMaps):
    """Boxes (x0, y0, z0, x1, y1) and materials of the run-grid cells."""
    both = np.stack([maps.depth, maps.material]).astype(np.int64)
    row_starts = np.flatnonzero(np.r_[True, (both[:, 1:] != both[:, :-1]).any(axis=(0, 2))])
    col_starts = np.flatnonzero(np.r_[True, (both[:, :, 1:] != both[:, :, :-1]).any(axis=(0, 1))])
    rows, cols = maps.shape
    row_ends, col_ends = np.r_[row_starts[1:], rows], np.r_[col_starts[1:], cols]
    r0, c0 = np.meshgrid(row_starts, col_starts, indexing="ij")
    r1, c1 = np.meshgrid(row_ends, col_ends, indexing="ij")
    z0 = maps.depth[r0, c0].astype(np.float64)
    material = maps.material[r0, c0].astype(np.int64)
    return np.stack([c0, r0, z0, c1, r1], axis=-1).reshape(-1, 5).astype(np.float64), material.reshape(-1)


def trace_reference(maps: DetailMaps, origins: np.ndarray, directions: np.ndarray, chunk: int = 256) -> Hits:
    """First hits of rays given in map space, origins (..., 3) and directions (..., 3)."""
    shape = origins.shape[:-1]
    o = origins.reshape(-1, 3).astype(np.float64)
    d = directions.reshape(-1, 3).astype(np.float64)
    cells, cell_material = _cells(maps)
    bottom = float(maps.max_depth) + 1.0
    lo = cells[:, [0, 1, 2]]
    hi = np.column_stack([cells[:, 3], cells[:, 4], np.full(len(cells), bottom)])
    material = np.full(len(o), MISS)
    face = np.full(len(o), MISS)
    t_hit = np.full(len(o), np.inf)
    # A zero direction component becomes a tiny one: the slab test then needs no special case.
    d = np.where(np.abs(d) < 1e-12, 1e-12, d)
    inv_d = 1.0 / d
    # Only the part of a ray between depth 0 and the bottom can hit: its footprint bounds the cells
    # worth testing for a chunk of neighbouring pixels.
    t_top, t_bottom = -o[:, 2] * inv_d[:, 2], (bottom - o[:, 2]) * inv_d[:, 2]
    t_enter = np.clip(np.minimum(t_top, t_bottom), 0, None)
    t_leave = np.clip(np.maximum(t_top, t_bottom), 0, None)
    ends = np.stack([o + d * t_enter[:, None], o + d * t_leave[:, None]])[..., :2]
    for start in range(0, len(o), chunk):
        sl = slice(start, start + chunk)
        foot_lo, foot_hi = ends[:, sl].min(axis=(0, 1)), ends[:, sl].max(axis=(0, 1))
        near = np.flatnonzero(np.all((lo[:, :2] <= foot_hi) & (hi[:, :2] >= foot_lo), axis=1))
        oc, inv, dc = o[sl, None, :], inv_d[sl, None, :], d[sl, None, :]
        t1, t2 = (lo[near][None] - oc) * inv, (hi[near][None] - oc) * inv
        t_near_axis = np.minimum(t1, t2)
        t_near = t_near_axis.max(axis=2)
        t_far = np.maximum(t1, t2).min(axis=2)
        valid = (t_near <= t_far) & (t_near >= 0)
        t_near = np.where(valid, t_near, np.inf)
        if len(near) == 0:
            continue
        best = np.argmin(t_near, axis=1)
        rows = np.arange(len(best))
        t_best = t_near[rows, best]
        hit = np.isfinite(t_best)
        axis = np.argmax(t_near_axis[rows, best], axis=1)
        sign = np.sign(dc[rows, 0, axis])
        face_id = np.select(
            [axis == 2, (axis == 0) & (sign > 0), axis == 0, sign > 0],
            [FACE_FRONT, FACE_NEG_X, FACE_POS_X, FACE_NEG_Y],
            FACE_POS_Y,
        )
        material[sl] = np.where(hit, cell_material[near][best], MISS)
        face[sl] = np.where(hit, face_id, MISS)
        t_hit[sl] = t_best
    point = np.where(np.isfinite(t_hit)[:, None], o + d * np.where(np.isfinite(t_hit), t_hit, 0)[:, None], np.nan)
    return Hits(material.reshape(shape), face.reshape(shape), point.reshape(*shape, 3))
