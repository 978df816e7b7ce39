"""Exterior wall texture: one window bay whose alpha marks the glass (paper §2.3).

Alpha 0 is the window through which the interior is seen; everywhere else the
wall is opaque. The glass keeps a wall margin on both sides so transparency
never reaches a building corner (paper §2.4, fig. 8). The bay tiles in u and v.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from . import _draw as d

WALL_MARGIN = 0.3  # fraction of the bay width left of the glass (and right of it)
GLASS_BOTTOM, GLASS_TOP = 0.3, 0.82


@lru_cache(maxsize=16)
def _facade(size: int, seed: int, material: str) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    rng = np.random.default_rng([seed, 17])
    u, v = d.uv_grid(size)
    # The glass rectangle is snapped to whole texels so alpha matches it exactly.
    c0 = int(round(WALL_MARGIN * size))
    r0, r1 = int(round(GLASS_BOTTOM * size)), int(round(GLASS_TOP * size))
    u0, u1, v0, v1 = c0 / size, (size - c0) / size, r0 / size, r1 / size

    if material == "brick":
        base = np.array([0.58, 0.3, 0.22]) * (1 + 0.08 * rng.standard_normal(3))
        img = d.canvas(size, size, base)
        courses, bricks = 16, 4
        row = np.floor(v * courses)
        x = u * bricks + 0.5 * (row % 2)
        tone = 0.82 + 0.3 * d.cell_random((np.floor(x) % bricks) * 61 + row, seed, 5)
        d.shade(img, tone * (0.9 + 0.15 * d.fbm(u, v, 8, 3, seed)))
        joint = ((v * courses) % 1 < 0.14) | (x % 1 < 0.05)
        d.paint(img, joint, (0.68, 0.64, 0.58))
        trim = np.array([0.85, 0.83, 0.78])
    else:
        base = np.array([0.86, 0.8, 0.68]) * (1 + 0.04 * rng.standard_normal(3))
        img = d.canvas(size, size, base)
        d.shade(img, 0.88 + 0.16 * d.fbm(u, v, 4, 4, seed))
        trim = base * 0.78

    # A string course marks each storey, so stacked bays read as floors.
    d.paint(img, v < 0.035, trim * 0.92)
    d.shade(img, 0.8, (v >= 0.035) & (v < 0.045))

    frame_w, frame = 0.035, np.array([0.93, 0.93, 0.9]) if material == "brick" else np.array([0.25, 0.24, 0.23])
    d.paint(img, d.rect(u, v, u0 - frame_w, v0 - frame_w, u1 + frame_w, v1 + frame_w), frame)
    # The top and left inner edges of the frame are in the shadow of the recess.
    d.shade(img, 0.7, d.rect(u, v, u0 - frame_w, v1, u1 + frame_w, v1 + frame_w * 0.5))
    d.shade(img, 0.8, d.rect(u, v, u0 - frame_w * 0.5, v0, u0, v1))

    sill = d.rect(u, v, u0 - 0.07, v0 - 0.075, u1 + 0.07, v0 - frame_w)
    d.paint(img, sill, trim, 0.95 + 0.1 * (v - (v0 - 0.075)) / 0.04)
    d.shade(img, 0.65, d.rect(u, v, u0 - 0.06, v0 - 0.095, u1 + 0.06, v0 - 0.075))

    lintel = d.rect(u, v, u0 - 0.06, v1 + frame_w, u1 + 0.06, v1 + 0.1)
    d.paint(img, lintel, trim)
    if material == "brick":
        d.shade(img, 0.8, lintel & ((u * 24) % 1 < 0.1))
    d.shade(img, 0.85, d.rect(u, v, u0 - 0.06, v1 + frame_w, u1 + 0.06, v1 + frame_w + 0.012))

    glass = d.rect(u, v, u0, v0, u1, v1)
    d.paint(img, glass, (0.1, 0.12, 0.15))
    return d.frozen(d.to_rgba8(img, alpha=~glass)), (u0, v0, u1, v1)


def facade_texture(
    size: int = 128, seed: int = 0, material: str | None = None
) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """One window bay of a building exterior and its glass rectangle.

    Returns (image, (u0, v0, u1, v1)): image is (size, size, 4) uint8 sRGB RGBA, row 0
    = v = 0 (the storey line); alpha is 0 exactly on the glass texels [u0,u1) x [v0,v1)
    and 255 elsewhere. The glass is centred in u with a wall margin of WALL_MARGIN (at
    least 15%) on both sides. `material` is "plaster" or "brick" (default: by seed).
    """
    if material is None:
        material = ("plaster", "brick")[seed % 2]
    if material not in ("plaster", "brick"):
        raise ValueError(f"facade material must be 'plaster' or 'brick', got {material!r}")
    if size < 16:
        raise ValueError(f"facade_texture needs size >= 16, got {size}")
    return _facade(int(size), int(seed), material)
