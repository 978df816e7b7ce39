"""The grammar's source of randomness (§3.1): a noise texture sampled at a scope's lower-left
corner, and the per-facade seed vector that translates the start scope."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

NOISE_SIZE = 256
NOISE_DENSITY = 8.0  # noise texels per metre: corners are rounded to 1/8 m before the lookup
_SKEW = 37  # rows are shifted against each other so the noise does not repeat along an axis


@lru_cache(maxsize=1)
def noise_texture() -> np.ndarray:
    """(NOISE_SIZE, NOISE_SIZE) float32 uniform values in [0, 1)."""
    values = np.random.default_rng(20110601).random((NOISE_SIZE, NOISE_SIZE), dtype=np.float32)
    values.flags.writeable = False
    return values


def noise_at(corner: np.ndarray) -> np.ndarray:
    """r in [0, 1) for each (x, y) corner, exactly as shaders/grammar/eval.glsl computes it."""
    cell = np.floor(corner.astype(np.float32) * np.float32(NOISE_DENSITY) + np.float32(0.5)).astype(np.int32)
    x = (cell[..., 0] + cell[..., 1] * _SKEW) & (NOISE_SIZE - 1)
    y = cell[..., 1] & (NOISE_SIZE - 1)
    return noise_texture()[y, x]


def seed_cells(seeds) -> np.ndarray:
    """Integer seed vectors in noise cells (1/8 m), (n, 2) int32, for integer seeds (a hash)."""
    h = np.asarray(seeds, dtype=np.uint64) * np.uint64(0x9E3779B97F4A7C15)
    h ^= h >> np.uint64(31)
    x = (h & np.uint64(2047)).astype(np.int32)
    y = ((h >> np.uint64(11)) & np.uint64(2047)).astype(np.int32)
    return np.stack([x, y], axis=-1)


def seed_vector(seed: int) -> tuple[float, float]:
    """The facade's seed vector s (metres, on the noise grid so every facade rounds alike)."""
    x, y = seed_cells([seed])[0]
    return float(x) / NOISE_DENSITY, float(y) / NOISE_DENSITY
