"""Curtain fabric: vertical folds that tile horizontally."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ._draw import fbm, frozen, to_rgba8, uv_grid


def fold_shade(u, folds: int) -> np.ndarray:
    """Brightness of fabric hanging in `folds` vertical folds across u in [0, 1]."""
    wave = np.cos(2 * np.pi * folds * np.asarray(u, np.float32))
    # Folds are lit on their crests and darker in the creases; the power keeps creases narrow.
    return (0.55 + 0.45 * ((wave + 1) * 0.5) ** 0.7).astype(np.float32)


@lru_cache(maxsize=16)
def _curtain(size: int, colour: tuple[float, float, float], folds: int, seed: int) -> np.ndarray:
    u, v = uv_grid(size)
    weave = 0.92 + 0.08 * fbm(u * 4, v, cells=8, octaves=2, seed=seed)
    light = fold_shade(u, folds) * weave * (0.9 + 0.1 * v)
    img = np.asarray(colour, np.float32) * light[..., None]
    hem = v < 0.06
    img[hem] *= 0.8
    return frozen(to_rgba8(img))


def curtain_texture(
    size: int = 64,
    colour: tuple[float, float, float] = (0.78, 0.62, 0.42),
    folds: int = 4,
    seed: int = 0,
) -> np.ndarray:
    """(size, size, 4) uint8 RGBA fabric with `folds` vertical folds; opaque, tiles in u.

    Row 0 is the bottom (the hem). Colour is sRGB in [0, 1].
    """
    return _curtain(int(size), tuple(float(c) for c in colour), int(folds), int(seed))
