"""Brute-force ray casting of triangle lists in numpy (the reference for rasterised visibility)."""

from __future__ import annotations

import numpy as np


def intersect(origin: np.ndarray, dirs: np.ndarray, triangles: np.ndarray, chunk: int = 2048):
    """Nearest hit of rays (origin (3,), dirs (N, 3)) with triangles (T, 3, 3), both sides.
    Returns (t (N,), triangle index (N,), barycentrics (N, 3)); t = inf and index -1 on a miss."""
    n = len(dirs)
    best_t = np.full(n, np.inf)
    best_i = np.full(n, -1, dtype=np.int64)
    best_b = np.zeros((n, 3))
    a = triangles[:, 0]
    e1 = triangles[:, 1] - a
    e2 = triangles[:, 2] - a
    for start in range(0, n, chunk):
        d = dirs[start : start + chunk][:, None, :]
        p = np.cross(d, e2[None])
        det = np.sum(e1[None] * p, axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = origin - a
            u = np.sum(s[None] * p, axis=-1) * inv
            q = np.cross(s, e1)
            v = np.sum(d * q[None], axis=-1) * inv
            t = np.sum(e2 * q, axis=-1)[None] * inv
            ok = (np.abs(det) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        t = np.where(ok, t, np.inf)
        idx = np.argmin(t, axis=1)
        rows = np.arange(len(idx))
        tmin = t[rows, idx]
        hit = np.isfinite(tmin)
        sl = slice(start, start + len(idx))
        best_t[sl] = tmin
        best_i[sl] = np.where(hit, idx, -1)
        best_b[sl] = np.stack([1 - u[rows, idx] - v[rows, idx], u[rows, idx], v[rows, idx]], axis=1)
    return best_t, best_i, best_b
