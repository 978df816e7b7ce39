"""Numpy twin of shaders/city/ground_normal.glsl: the upward unit normal of each ground triangle."""

from __future__ import annotations

import numpy as np


def face_normals(vertices: np.ndarray) -> np.ndarray:
    """(N, 3) float32 unit normals, y up, of (N*3, >=3) scene triangle corners (upright ones: any side)."""
    t = np.asarray(vertices, np.float64)[:, :3].reshape(-1, 3, 3)
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    return np.where(n[:, 1:2] < 0, -n, n).astype(np.float32)
