"""numpy twin of shaders/common/hash.glsl: identical bits for identical inputs."""

from __future__ import annotations

import numpy as np

_MASK = np.uint64(0xFFFFFFFF)


def _u32(x) -> np.ndarray:
    return np.asarray(x).astype(np.int64).astype(np.uint64) & _MASK


def pcg_hash(v) -> np.ndarray:
    v = _u32(v)
    state = (v * np.uint64(747796405) + np.uint64(2891336453)) & _MASK
    word = (((state >> ((state >> np.uint64(28)) + np.uint64(4))) ^ state) * np.uint64(277803737)) & _MASK
    return ((word >> np.uint64(22)) ^ word) & _MASK


def hash3(x, y, z, salt) -> np.ndarray:
    """Hash of integer lattice points (int arrays, negative allowed) with a salt; uint64 holding 32 bits."""
    return pcg_hash(_u32(x) ^ pcg_hash(_u32(y) ^ pcg_hash(_u32(z) ^ pcg_hash(salt))))


def unit_float(h) -> np.ndarray:
    return (np.asarray(h, dtype=np.uint64) >> np.uint64(8)).astype(np.float64) / 16777216.0
