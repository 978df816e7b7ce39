"""The grammar's source of randomness (§3.1): a noise texture sampled at a scope's lower-left
corner, and the per-facade seed vector that translates the start scope.

Each rule draws from its own stream: its texel address shifts the noise lookup by a hashed
offset, so two choices made at the same corner (a wall and a window picked at the facade's
corner, or a floor's door and windows grouped by one RandStack) are independent.

Each facade of a building draws from its own stream too: the building's seed cells are hashed
with the facade's index (the direction its wall faces), so the sides of a building make different
random choices while one side stays the same from frame to frame."""

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


def stream_offset(stream) -> np.ndarray:
    """The noise-cell offset of a rule's stream (its address), (..., 2) int32, as eval.glsl hashes it."""
    h = np.asarray(stream).astype(np.uint32) * np.uint32(0x9E3779B1)
    h ^= h >> np.uint32(15)
    h = h * np.uint32(0x85EBCA77)
    return np.stack([(h >> np.uint32(8)) & np.uint32(255), h >> np.uint32(24)], axis=-1).astype(np.int32)


def noise_at(corner: np.ndarray, stream) -> np.ndarray:
    """r in [0, 1) for each (x, y) corner and rule stream, exactly as shaders/grammar/eval.glsl computes it."""
    cell = np.floor(corner.astype(np.float32) * np.float32(NOISE_DENSITY) + np.float32(0.5)).astype(np.int32)
    cell = cell + stream_offset(stream)
    x = (cell[..., 0] + cell[..., 1] * _SKEW) & (NOISE_SIZE - 1)
    y = cell[..., 1] & (NOISE_SIZE - 1)
    return noise_texture()[y, x]


def seed_cells(seeds) -> np.ndarray:
    """Integer seed vectors in noise cells (1/8 m), (n, 2) int32, for integer seeds: splitmix64,
    whose added constant makes seed 0 as random as any other; each cell is in [1, 2047], never 0."""
    z = np.asarray(seeds, dtype=np.uint64).reshape(-1) + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z ^= z >> np.uint64(31)
    x = np.uint64(1) + z % np.uint64(2047)
    y = np.uint64(1) + (z >> np.uint64(32)) % np.uint64(2047)
    return np.stack([x, y], axis=-1).astype(np.int32)


def seed_vector(seed: int) -> tuple[float, float]:
    """The facade's seed vector s (metres, on the noise grid so every facade rounds alike)."""
    x, y = seed_cells([seed])[0]
    return float(x) / NOISE_DENSITY, float(y) / NOISE_DENSITY


# A facade's index is its face's first room column (cityshade/scene/_wall_faces.py: 0 for the first
# face and for a round mass), below the 11 bits interior.glsl gives room columns.
FACADE_INDICES = 2047


def facade_cells(cells, face) -> np.ndarray:
    """The seed cells (n, 2) of facade `face` of buildings with seed cells `cells`, exactly as
    eval.glsl grammar_facade_cells(): facade 0 keeps the building's cells, the others hash them
    with their index (a 32-bit integer hash); every cell stays in [1, 2047]."""
    cells = np.asarray(cells, np.int64).reshape(-1, 2)
    face = np.broadcast_to(np.asarray(face, np.int64), len(cells)).astype(np.uint32)
    h = (cells[:, 0].astype(np.uint32) | (cells[:, 1].astype(np.uint32) << np.uint32(11))) ^ (
        face * np.uint32(0x9E3779B1)
    )
    h ^= h >> np.uint32(16)
    h = h * np.uint32(0x7FEB352D)
    h ^= h >> np.uint32(15)
    h = h * np.uint32(0x846CA68B)
    h ^= h >> np.uint32(16)
    hashed = np.stack(
        [np.uint32(1) + h % np.uint32(2047), np.uint32(1) + (h >> np.uint32(11)) % np.uint32(2047)], axis=-1
    )
    return np.where((face == 0)[:, None], cells, hashed).astype(np.int32)


def facade_seed_vector(seed: int, face: int) -> tuple[float, float]:
    """The seed vector s of one facade of the building with this seed (facade 0: seed_vector(seed))."""
    x, y = facade_cells(seed_cells([seed]), face)[0]
    return float(x) / NOISE_DENSITY, float(y) / NOISE_DENSITY
