"""numpy twin of the silhouette-fin geometry shader (shaders/trees/fins.glsl, §4.2.1).

For each triangle, N.V is computed per vertex; on every edge where its sign changes, the point
where the linearly interpolated N.V is zero becomes a fin vertex. Two such points make a fin:
V0, V1 on the silhouette and V2 = V1 + N1 w1, V3 = V0 + N0 w0 extruded along the interpolated
normals; a fin whose two silhouette points coincide is dropped as degenerate.
"""

from __future__ import annotations

import numpy as np


def fin_width(points: np.ndarray, eye: np.ndarray, depth: float, fade: tuple[float, float]) -> np.ndarray:
    """Fin width at each point: `depth` near the eye, falling to 0 across the fade band (fig. 4-8)."""
    d = np.linalg.norm(points - eye, axis=-1)
    t = np.clip((d - fade[0]) / (fade[1] - fade[0]), 0.0, 1.0)
    return depth * (1.0 - t * t * (3.0 - 2.0 * t))


def extrude_fins(positions: np.ndarray, normals: np.ndarray, eye, depth: float, fade: tuple[float, float] = (1e9, 2e9)):
    """Fins of a triangle list. positions, normals: (T, 3, 3) world space, per-vertex smooth normals.

    Returns (triangle index (F,), quads (F, 4, 3) as V0, V1, V2, V3) in triangle order, the order
    the geometry shader emits them in.
    """
    eye = np.asarray(eye, float)
    positions = np.asarray(positions, float)
    normals = np.asarray(normals, float)
    view = eye - positions
    facing = np.sum(normals * view, axis=-1) / np.linalg.norm(view, axis=-1)  # (T, 3)
    front = facing > 0.0
    found = []
    for e in range(3):
        a, b = e, (e + 1) % 3
        cross = front[:, a] != front[:, b]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = facing[:, a] / (facing[:, a] - facing[:, b])
        t = np.where(cross, t, 0.0)[:, None]
        p = positions[:, a] * (1 - t) + positions[:, b] * t
        n = normals[:, a] * (1 - t) + normals[:, b] * t
        n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-12)
        found.append((cross, p, n))
    tris, quads = [], []
    for k in range(len(positions)):
        points = [(p[k], n[k]) for cross, p, n in found if cross[k]][:2]
        if len(points) < 2 or np.linalg.norm(points[0][0] - points[1][0]) < 1e-6:
            continue
        (p0, n0), (p1, n1) = points
        w0, w1 = fin_width(np.array([p0, p1]), eye, depth, fade)
        if max(w0, w1) <= 0.0:
            continue
        tris.append(k)
        quads.append([p0, p1, p1 + n1 * w1, p0 + n0 * w0])
    return np.array(tris, int), np.array(quads, float).reshape(-1, 4, 3)
