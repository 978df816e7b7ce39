"""Procedural tree textures, generated deterministically in numpy (no downloaded assets).

- Bark: one layer per species; colour + height (RGBA) and a tangent-space normal map, all
  tileable so the trunk's UVs can repeat. The height map drives relief mapping and the fins.
- Leaf atlas: 2x2 cells (broad leaves, small leaves, needle cluster, frond) with alpha.
  Its transparent texels carry the colour of the nearest leaves (push-pull fill), so the
  mipmaps' colour stays the leaves' colour where they average leaf and gap; alpha is untouched.
  Its companion "leaf detail" map holds the V-shaped normal (§4.4.2, RG) and the per-leaf
  depth offset used for leaf self-shadowing (fig. 4-11, B): one constant per leaf.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..gl import linear_to_srgb, srgb_to_linear

BARK_SIZE = 256
ATLAS_CELL = 256
ATLAS_CELLS = 2  # per side


@dataclass(frozen=True)
class BarkTextures:
    color_height: np.ndarray  # (layers, H, W, 4) uint8: rgb colour, a height (1 = outermost)
    normal: np.ndarray  # (layers, H, W, 4) uint8: tangent-space normal * 0.5 + 0.5


@dataclass(frozen=True)
class LeafTextures:
    color: np.ndarray  # (H, W, 4) uint8, alpha = leaf coverage
    detail: np.ndarray  # (H, W, 4) uint8: rg V-shaped normal, b depth offset, a leaf id / 255


def _to_uint8(values) -> np.ndarray:
    """[0, 1] floats -> uint8, rounded."""
    return np.round(np.clip(np.asarray(values), 0, 1) * 255).astype(np.uint8)


def periodic_noise(shape, rng, power: float, stretch=(1.0, 1.0)) -> np.ndarray:
    """Tileable noise in [0, 1]: a random spectrum with 1/f^power falloff; stretch > 1 along an
    axis (rows, columns) makes the noise smoother along it."""
    h, w = shape
    fy = np.fft.fftfreq(h)[:, None] * h * stretch[0]
    fx = np.fft.rfftfreq(w)[None, :] * w * stretch[1]
    f = np.sqrt(fx**2 + fy**2)
    amplitude = np.where(f > 0, 1.0 / np.maximum(f, 1e-9) ** power, 0.0)
    spectrum = amplitude * np.exp(2j * np.pi * rng.uniform(size=amplitude.shape))
    n = np.fft.irfft2(spectrum, s=shape)
    return (n - n.min()) / (n.max() - n.min())


def height_to_normal(height: np.ndarray, strength: float) -> np.ndarray:
    """Tangent-space normals (x along u, y along v, z out) of a tileable height map."""
    dx = (np.roll(height, -1, axis=1) - np.roll(height, 1, axis=1)) * 0.5 * strength
    dy = (np.roll(height, -1, axis=0) - np.roll(height, 1, axis=0)) * 0.5 * strength
    n = np.stack([-dx, -dy, np.ones_like(height)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


_BARK_STYLES = (
    # dark rgb, light rgb, furrow stretch along v, ridge sharpness
    ((0.16, 0.11, 0.07), (0.45, 0.37, 0.28), 6.0, 1.6),  # oak: deep vertical furrows
    ((0.22, 0.10, 0.06), (0.55, 0.33, 0.22), 2.0, 1.0),  # fir: reddish plates
    ((0.35, 0.35, 0.32), (0.72, 0.71, 0.66), 3.0, 0.7),  # poplar: grey, shallow
)


@lru_cache(maxsize=1)
def bark_textures() -> BarkTextures:
    rng = np.random.default_rng(7)
    colors, normals = [], []
    for dark, light, stretch, sharp in _BARK_STYLES:
        coarse = periodic_noise((BARK_SIZE, BARK_SIZE), rng, 1.6, (stretch, 1.0))
        fine = periodic_noise((BARK_SIZE, BARK_SIZE), rng, 1.0, (stretch * 0.5, 1.0))
        # Fold the noise about its middle: narrow furrows where it crosses, broad plates between.
        plates = np.clip(np.abs(coarse - 0.5) * 2.6, 0, 1) ** (1.0 / sharp)
        # Plates break across the grain too, so a silhouette (which looks along the grain) is bumpy.
        breaks = np.clip(np.abs(periodic_noise((BARK_SIZE, BARK_SIZE), rng, 1.3, (1.0, 4.0)) - 0.5) * 3.0, 0, 1)
        height = plates * breaks * 0.8 + fine * 0.2
        height = (height - height.min()) / (height.max() - height.min())
        tint = periodic_noise((BARK_SIZE, BARK_SIZE), rng, 2.0)[..., None]
        rgb = np.array(dark) + (np.array(light) - np.array(dark)) * (height[..., None] * 0.8 + tint * 0.2)
        colors.append(np.concatenate([rgb, height[..., None]], axis=-1))
        normals.append(
            np.concatenate([height_to_normal(height, 6.0) * 0.5 + 0.5, np.ones_like(height)[..., None]], axis=-1)
        )
    return BarkTextures(_to_uint8(colors), _to_uint8(normals))


def _paint_leaf(cell, detail, ids, leaf_id, base, axis, length, width, color, depth):
    """Rasterises one leaf (pointed ellipse with a midrib) into a cell, in painter's order."""
    size = cell.shape[0]
    y, x = np.mgrid[0:size, 0:size] + 0.5
    rel = np.stack([x - base[0], y - base[1]], axis=-1)
    along = rel @ axis / length
    side_dir = np.array([-axis[1], axis[0]])
    across = rel @ side_dir
    profile = np.sin(np.pi * np.clip(along, 0, 1)) ** 0.7 * width
    inside = (along > 0) & (along < 1) & (np.abs(across) < profile)
    stem = (along > -0.25) & (along <= 0) & (np.abs(across) < 1.2)
    vein = inside & (np.abs(across) < 1.0)
    shade = 0.85 + 0.15 * np.clip(along, 0, 1)[..., None] - 0.25 * vein[..., None]
    cell[inside | stem, :3] = (np.array(color) * shade)[inside | stem]
    cell[inside | stem, 3] = 1.0
    # V-shaped normal: each half of the leaf tilts away from the midrib (§4.4.2).
    tilt = 0.45 * np.sign(across)[..., None] * side_dir
    n = np.concatenate([tilt, np.ones(across.shape + (1,))], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    detail[inside | stem, :2] = n[inside | stem, :2] * 0.5 + 0.5
    detail[inside | stem, 2] = depth
    ids[inside | stem] = leaf_id


def _leaf_cell(rng, count, length, width, hue, spread_from_center):
    size = ATLAS_CELL
    cell = np.zeros((size, size, 4))
    detail = np.zeros((size, size, 4))
    detail[..., :2] = 0.5
    ids = np.zeros((size, size), np.int32)
    for leaf in range(1, count + 1):
        angle = rng.uniform(0, 2 * np.pi)
        axis = np.array([np.cos(angle), np.sin(angle)])
        if spread_from_center:  # needles radiate from the card centre
            base = np.array([size / 2, size / 2]) + axis * rng.uniform(0, 20)
        else:
            base = rng.uniform(size * 0.25, size * 0.75, 2) - axis * length * 0.3
        color = np.array(hue) * rng.uniform(0.75, 1.15) + rng.normal(0, 0.02, 3)
        _paint_leaf(
            cell,
            detail,
            ids,
            leaf,
            base,
            axis,
            length * rng.uniform(0.8, 1.1),
            width * rng.uniform(0.8, 1.2),
            np.clip(color, 0, 1),
            rng.uniform(0, 1),
        )
    detail[..., 3] = (ids % 251) / 255.0
    return cell, detail


def _frond_cell(rng):
    """A spray of needles on both sides of a central stem that runs along v."""
    size = ATLAS_CELL
    cell = np.zeros((size, size, 4))
    detail = np.zeros((size, size, 4))
    detail[..., :2] = 0.5
    ids = np.zeros((size, size), np.int32)
    leaf = 1
    for v in np.arange(6, size - 6, 7):
        for side in (-1, 1):
            axis = np.array([side * 0.85, 0.5])
            axis /= np.linalg.norm(axis)
            length = 70 * (1 - 0.5 * v / size) * rng.uniform(0.85, 1.1)
            hue = np.array((0.10, 0.28, 0.12)) * rng.uniform(0.8, 1.2)
            _paint_leaf(cell, detail, ids, leaf, np.array([size / 2, v]), axis, length, 2.2, hue, rng.uniform(0, 1))
            leaf += 1
    stem = np.abs(np.arange(size) + 0.5 - size / 2) < 2.5
    cell[:, stem] = (0.25, 0.17, 0.08, 1.0)
    detail[..., 3] = (ids % 251) / 255.0
    return cell, detail


def fill_transparent(cell: np.ndarray) -> np.ndarray:
    """A square power-of-two RGBA cell ([0, 1] sRGB colour, alpha coverage) whose transparent
    texels take the mean linear colour of the opaque texels in the smallest aligned block around
    them that has any (push-pull): the GPU's box-filtered colour mips then average leaves with
    leaf-coloured gaps instead of black ones. Opaque texels and alpha are kept."""
    coverage = cell[..., 3:]
    weighted, weight = srgb_to_linear(cell[..., :3]) * coverage, coverage
    pyramid = [(weighted, weight)]
    while weight.shape[0] > 1:  # pull: sums of colour x coverage and of coverage, per 2x2 block
        n = weight.shape[0] // 2
        weighted = weighted.reshape(n, 2, n, 2, 3).sum(axis=(1, 3))
        weight = weight.reshape(n, 2, n, 2, 1).sum(axis=(1, 3))
        pyramid.append((weighted, weight))
    colour = pyramid[-1][0] / np.maximum(pyramid[-1][1], 1e-12)
    for weighted, weight in reversed(pyramid[:-1]):  # push: empty blocks inherit the coarser mean
        coarse = colour.repeat(2, axis=0).repeat(2, axis=1)
        colour = np.where(weight > 0, weighted / np.maximum(weight, 1e-12), coarse)
    filled = cell.copy()
    transparent = cell[..., 3] == 0
    filled[transparent, :3] = linear_to_srgb(colour[transparent])
    return filled


@lru_cache(maxsize=1)
def leaf_textures() -> LeafTextures:
    rng = np.random.default_rng(11)
    cells = [
        _leaf_cell(rng, 14, 95, 22, (0.20, 0.42, 0.10), False),  # broad leaves (oak)
        _leaf_cell(rng, 22, 60, 20, (0.28, 0.48, 0.14), False),  # small round leaves (poplar)
        _leaf_cell(rng, 60, 100, 2.0, (0.10, 0.26, 0.12), True),  # needle cluster (fir)
        _frond_cell(rng),
    ]
    n, s = ATLAS_CELLS, ATLAS_CELL
    color = np.zeros((n * s, n * s, 4))
    detail = np.zeros((n * s, n * s, 4))
    for index, (c, d) in enumerate(cells):
        row, col = divmod(index, n)
        color[row * s : (row + 1) * s, col * s : (col + 1) * s] = fill_transparent(c)
        detail[row * s : (row + 1) * s, col * s : (col + 1) * s] = d
    return LeafTextures(_to_uint8(color), _to_uint8(detail))
