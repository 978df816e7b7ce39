"""Vectorised drawing helpers shared by the procedural textures.

Images are float32 arrays [row, col, 3] in sRGB-encoded [0, 1] while they are
painted, and row 0 is the bottom (v = 0) so they upload to OpenGL as they are.
Coordinates are texel centres: u = (col + 0.5) / width, v = (row + 0.5) / height.
"""

from __future__ import annotations

import numpy as np

_HASH_MULT = np.array([0x8DA6B343, 0xD8163841, 0xCB1AB31F], dtype=np.uint64)


def uv_grid(height: int, width: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Texel-centre coordinates (u, v), each (height, width) float32."""
    width = height if width is None else width
    u = (np.arange(width, dtype=np.float32) + 0.5) / width
    v = (np.arange(height, dtype=np.float32) + 0.5) / height
    return np.broadcast_to(u[None, :], (height, width)), np.broadcast_to(v[:, None], (height, width))


def canvas(height: int, width: int, colour) -> np.ndarray:
    return np.broadcast_to(np.asarray(colour, np.float32), (height, width, 3)).copy()


def rect(u, v, u0, v0, u1, v1) -> np.ndarray:
    """Mask of the axis-aligned rectangle [u0, u1) x [v0, v1)."""
    return (u >= u0) & (u < u1) & (v >= v0) & (v < v1)


def ellipse(u, v, cu, cv, ru, rv) -> np.ndarray:
    return ((u - cu) / ru) ** 2 + ((v - cv) / rv) ** 2 < 1.0


def paint(img: np.ndarray, mask: np.ndarray, colour, shade=None) -> None:
    """Fill `mask` with `colour`, optionally multiplied by a per-texel `shade`."""
    colour = np.asarray(colour, np.float32)
    if shade is None:
        img[mask] = colour
    else:
        img[mask] = colour * np.asarray(shade, np.float32)[mask][:, None]


def shade(img: np.ndarray, factor, mask=None) -> None:
    """Multiply the image by a per-texel factor (where `mask`)."""
    factor = np.broadcast_to(np.asarray(factor, np.float32), img.shape[:2])
    if mask is None:
        img *= factor[..., None]
    else:
        img[mask] *= factor[mask][:, None]


def hash01(ix: np.ndarray, iy: np.ndarray, seed: int) -> np.ndarray:
    """Deterministic pseudo-random value in [0, 1) per integer lattice point."""
    with np.errstate(over="ignore"):  # the hash relies on wrap-around multiplication
        return _mix_bits(ix, iy, seed)


def _mix_bits(ix, iy, seed: int) -> np.ndarray:
    h = (
        (ix.astype(np.int64).astype(np.uint64) * _HASH_MULT[0])
        ^ (iy.astype(np.int64).astype(np.uint64) * _HASH_MULT[1])
        ^ (np.uint64(seed & 0xFFFFFFFF) * _HASH_MULT[2])
    )
    h ^= h >> np.uint64(29)
    h *= np.uint64(0xBF58476D1CE4E5B9)
    h ^= h >> np.uint64(32)
    return (h & np.uint64(0xFFFFFF)).astype(np.float32) / np.float32(0x1000000)


def value_noise(x, y, seed: int = 0, period: int | None = None) -> np.ndarray:
    """Smooth value noise in [0, 1] at continuous lattice coordinates.

    With `period`, the lattice wraps so the noise tiles every `period` units.
    """
    x = np.asarray(x, np.float32)
    y = np.asarray(y, np.float32)
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx = x - x0
    fy = y - y0
    fx = fx * fx * (3 - 2 * fx)
    fy = fy * fy * (3 - 2 * fy)
    ix = x0.astype(np.int64)
    iy = y0.astype(np.int64)
    # Hash each lattice point once into a table, then gather the four corners.
    xmin, ymin = int(ix.min()), int(iy.min())
    lx = np.arange(xmin, int(ix.max()) + 2)
    ly = np.arange(ymin, int(iy.max()) + 2)
    if period is not None:
        lx, ly = lx % period, ly % period
    table = hash01(lx[None, :], ly[:, None], seed)
    flat = table.ravel()
    row = table.shape[1]
    corner = (iy - ymin) * row + (ix - xmin)
    a = flat[corner]
    b = flat[corner + 1]
    c = flat[corner + row]
    d = flat[corner + row + 1]
    return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy


def fbm(u, v, cells: int, octaves: int = 4, seed: int = 0, tile: bool = True) -> np.ndarray:
    """Fractal sum of value noise over [0,1]^2 in [0, 1]; tiles when `tile`."""
    total = np.zeros(np.broadcast(u, v).shape, np.float32)
    amplitude, norm = 1.0, 0.0
    for octave in range(octaves):
        n = cells << octave
        total += amplitude * value_noise(u * n, v * n, seed + 101 * octave, n if tile else None)
        norm += amplitude
        amplitude *= 0.5
    return total / norm


def cell_random(index, seed: int, salt: int = 0) -> np.ndarray:
    """A random value in [0, 1) per integer cell index (e.g. per plank or brick)."""
    index = np.asarray(index)
    return hash01(index, np.full_like(index, salt), seed)


def to_rgba8(img: np.ndarray, alpha=None) -> np.ndarray:
    """float sRGB [0,1] (H, W, 3) -> uint8 RGBA; alpha is a mask or None (opaque)."""
    rgb = np.clip(img * 255.0 + 0.5, 0, 255).astype(np.uint8)
    a = np.full(img.shape[:2] + (1,), 255, np.uint8)
    if alpha is not None:
        a[..., 0] = np.where(alpha, 255, 0)
    return np.concatenate([rgb, a], axis=-1)


def frozen(array: np.ndarray) -> np.ndarray:
    """Mark a cached result read-only so a caller cannot alter the cache."""
    array.flags.writeable = False
    return array


def capsule(u, v, p0, p1, radius) -> np.ndarray:
    """Mask of the texels within `radius` of the segment p0-p1 (a limb, a stem)."""
    (ax, ay), (bx, by) = p0, p1
    dx, dy = bx - ax, by - ay
    t = np.clip(((u - ax) * dx + (v - ay) * dy) / max(dx * dx + dy * dy, 1e-12), 0.0, 1.0)
    return (u - ax - t * dx) ** 2 + (v - ay - t * dy) ** 2 < radius * radius


def trapezoid(u, v, centre, v0, v1, half_bottom, half_top) -> np.ndarray:
    """Mask of a symmetric trapezoid between heights v0 and v1 (a lamp shade, a pot)."""
    t = (v - v0) / (v1 - v0)
    return (t >= 0) & (t < 1) & (np.abs(u - centre) < half_bottom + (half_top - half_bottom) * t)
