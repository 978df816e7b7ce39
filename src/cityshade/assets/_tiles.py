"""The facade tile array: atomic elements (walls, windows, doors, ...) a facade grammar composes.

Each tile has three planes in one RGBA8 texture array (layer = 3 * index + plane):
colour (rgb, alpha = the tile's shape), normal (tangent space, 0.5 + 0.5 n, alpha = shape) and
specular (r = intensity, g = shininess / 128, b = glass, alpha = shape). Bit masks (arched and
round openings, ...) are tiles too: white with the bit in alpha. Every tile carries a semantic
label. Painted procedurally and deterministically; row 0 is the bottom (v = 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

import numpy as np

from . import _draw as d

# Semantic labels of the label AOV (index = value written per pixel; 0 = nothing).
LABELS = ("none", "wall", "window", "door", "balcony", "shop", "roof", "room", "cornice")
# A colour per label for label images (uint8 RGB).
LABEL_COLOURS = (
    (0, 0, 0),
    (200, 170, 130),
    (60, 120, 220),
    (150, 60, 30),
    (230, 200, 40),
    (220, 60, 160),
    (170, 40, 40),
    (90, 200, 120),
    (240, 240, 240),
)
PLANES = ("color", "normal", "specular")


@dataclass
class Paint:
    """One tile being painted: colour, shape alpha, height (for the normal map), specular, glass."""

    u: np.ndarray
    v: np.ndarray
    rgb: np.ndarray
    alpha: np.ndarray
    height: np.ndarray
    spec: np.ndarray
    glass: np.ndarray
    seed: int

    @classmethod
    def blank(cls, size: int, colour, seed: int) -> "Paint":
        u, v = d.uv_grid(size)
        zeros = np.zeros((size, size), np.float32)
        return cls(
            u,
            v,
            d.canvas(size, size, colour),
            np.ones((size, size), bool),
            zeros.copy(),
            np.full((size, size), 0.08, np.float32),
            np.zeros((size, size), bool),
            seed,
        )

    def fill(self, mask, colour, height=None, spec=None, tone=None):
        if tone is not None:
            tone = np.broadcast_to(np.asarray(tone, np.float32), mask.shape)
        d.paint(self.rgb, mask, colour, tone)
        if height is not None:
            self.height[mask] = height
        if spec is not None:
            self.spec[mask] = spec


# --------------------------------------------------------------------------- wall materials


def _masonry(p: Paint, rows: int, cols: int, mortar, colour, spread=0.18, mortar_width=0.07):
    """Running-bond courses: each course offset by half a unit, each unit tinted."""
    row = np.floor(p.v * rows)
    x = p.u * cols + 0.5 * (row % 2)
    col = np.floor(x)
    tint = 1.0 - spread / 2 + spread * d.cell_random(col * 131 + row, p.seed)
    grain = 0.9 + 0.2 * d.fbm(p.u, p.v, 16, 3, p.seed, tile=True)
    p.fill(np.ones_like(p.alpha), colour, height=1.0, tone=tint * grain)
    joint = ((p.v * rows) % 1 < mortar_width * rows / cols * 2) | ((x % 1) < mortar_width)
    p.fill(joint, mortar, height=0.0, tone=grain)


def _render_plaster(p: Paint, colour, cells=6):
    tone = 0.86 + 0.22 * d.fbm(p.u, p.v, cells, 4, p.seed)
    p.fill(np.ones_like(p.alpha), colour, tone=tone)
    p.height[:] = tone


def _panels(p: Paint, colour, joints=2):
    _render_plaster(p, colour, cells=3)
    joint = ((p.u * joints) % 1 < 0.02) | ((p.v * joints) % 1 < 0.02)
    p.fill(joint, np.asarray(colour) * 0.55, height=0.0)


def _roof(p: Paint):
    _masonry(p, 8, 5, (0.25, 0.12, 0.1), (0.55, 0.22, 0.16), spread=0.3, mortar_width=0.04)
    p.height[:] = (p.v * 8) % 1


# --------------------------------------------------------------------------- openings


def _arch_shape(u, v, top=0.72):
    """Rectangle below `top`, half-ellipse above: an arched opening filling the tile."""
    return (v < top) | d.ellipse(u, v, 0.5, top, 0.5, 1.0 - top)


def _glass(p: Paint, mask, tint=(0.22, 0.3, 0.38)):
    sky = 0.75 + 0.5 * p.v + 0.15 * np.sin(9 * p.u + 14 * p.v)
    p.fill(mask, tint, height=0.2, spec=0.9, tone=sky)
    p.glass |= mask


def _window(p: Paint, frame, panes=(2, 2), shape="rect", border=0.08, bar=0.035, shutters=None, open_glass=False):
    """A framed window; glass between the muntins; outside the shape the tile is transparent.
    With open_glass the panes are transparent too: a frame to lay over a hole into a room."""
    if shape == "arch":
        outer = _arch_shape(p.u, p.v)
        inner = _arch_shape((p.u - border) / (1 - 2 * border), (p.v - border) / (1 - 2 * border))
    elif shape == "round":
        outer = d.ellipse(p.u, p.v, 0.5, 0.5, 0.5, 0.5)
        inner = d.ellipse(p.u, p.v, 0.5, 0.5, 0.5 - border, 0.5 - border)
    else:
        outer = np.ones_like(p.alpha)
        inner = d.rect(p.u, p.v, border, border, 1 - border, 1 - border)
    p.alpha = outer
    p.fill(outer, frame, height=1.0, spec=0.2)
    _glass(p, inner)
    nx, ny = panes
    muntin = np.zeros_like(inner)
    for i in range(1, nx):
        muntin |= np.abs(p.u - i / nx) < bar / 2
    for j in range(1, ny):
        muntin |= np.abs(p.v - j / ny) < bar / 2
    p.fill(inner & muntin, frame, height=0.8, spec=0.2)
    p.glass &= ~muntin
    if shutters is not None:
        leaf = (p.u < 0.14) | (p.u > 0.86)
        slats = 0.8 + 0.2 * ((p.v * 24) % 1)
        p.fill(leaf & outer, shutters, height=0.9, spec=0.1, tone=slats)
        p.glass &= ~leaf
    if open_glass:
        p.alpha = p.alpha & ~p.glass
        p.glass[:] = False


def _door(p: Paint, wood, glass_panel=False, arch=False):
    shape = _arch_shape(p.u, p.v, 0.8) if arch else np.ones_like(p.alpha)
    p.alpha = shape
    grain = 0.85 + 0.25 * d.fbm(p.u * 0.3, p.v * 3, 16, 3, p.seed)
    p.fill(shape, wood, height=1.0, spec=0.15, tone=grain)
    if glass_panel:
        _glass(p, d.rect(p.u, p.v, 0.15, 0.3, 0.85, 0.9) & shape)
    else:
        for v0, v1 in ((0.08, 0.42), (0.52, 0.9)):
            panel = d.rect(p.u, p.v, 0.15, v0, 0.85, v1) & shape
            p.fill(panel, np.asarray(wood) * 0.8, height=0.6, tone=grain)
    knob = d.ellipse(p.u, p.v, 0.8, 0.47, 0.035, 0.02)
    p.fill(knob, (0.8, 0.7, 0.3), height=1.0, spec=0.9)


def _cornice(p: Paint, colour, bands=((0.0, 0.2, 0.5), (0.2, 0.45, 0.8), (0.45, 0.75, 1.0), (0.75, 1.0, 0.7))):
    for v0, v1, h in bands:
        band = d.rect(p.u, p.v, 0, v0, 1, v1)
        p.fill(band, colour, height=h, tone=0.7 + 0.3 * h)
    dentil = d.rect(p.u, p.v, 0, 0.2, 1, 0.45) & ((p.u * 8) % 1 < 0.5)
    p.fill(dentil, np.asarray(colour) * 0.75, height=0.6)


def _rail(p: Paint, metal, bars=8):
    rail = (p.v > 0.9) | (p.v < 0.06) | ((p.u * bars) % 1 < 0.12)
    p.alpha = rail
    p.fill(rail, metal, height=1.0, spec=0.6)


def _shop(p: Paint, frame, sign):
    p.fill(np.ones_like(p.alpha), frame, height=1.0, spec=0.3)
    p.fill(d.rect(p.u, p.v, 0, 0.78, 1, 1), sign, height=1.0, spec=0.4)
    letters = d.rect(p.u, p.v, 0.15, 0.84, 0.85, 0.94) & ((p.u * 14) % 1 < 0.6)
    p.fill(letters, (0.95, 0.93, 0.85), height=1.0)
    _glass(p, d.rect(p.u, p.v, 0.05, 0.06, 0.62, 0.72), tint=(0.3, 0.34, 0.36))
    _glass(p, d.rect(p.u, p.v, 0.7, 0.02, 0.95, 0.72), tint=(0.26, 0.3, 0.33))


def _awning(p: Paint, colour):
    stripe = (p.u * 6) % 1 < 0.5
    p.alpha = p.v > 0.05 + 0.08 * np.abs(np.sin(p.u * np.pi * 6))
    p.fill(p.alpha, (0.95, 0.93, 0.88), height=1.0)
    p.fill(p.alpha & stripe, colour, height=1.0)


# --------------------------------------------------------------------------- rooms (Intrusion faces)


def _wallpaper(p: Paint, colour, picture):
    _render_plaster(p, colour, cells=4)
    p.fill((p.u * 10) % 1 < 0.1, np.asarray(colour) * 0.9)
    p.fill(p.v < 0.06, (0.3, 0.22, 0.16), height=0.5)
    p.fill(d.rect(p.u, p.v, 0.3, 0.45, 0.7, 0.75), (0.25, 0.2, 0.12))
    p.fill(d.rect(p.u, p.v, 0.33, 0.48, 0.67, 0.72), picture)


def _floor(p: Paint):
    column = np.floor(p.u * 8)
    tone = 0.8 + 0.3 * d.cell_random(column * 7 + np.floor(p.v * 2 + column * 0.37), p.seed)
    p.fill(np.ones_like(p.alpha), (0.5, 0.34, 0.2), tone=tone)
    p.fill((p.u * 8) % 1 < 0.05, (0.25, 0.16, 0.1))


def _ceiling(p: Paint):
    r = np.hypot(p.u - 0.5, p.v - 0.5)
    p.fill(np.ones_like(p.alpha), (0.92, 0.9, 0.86), tone=1 + 0.3 * np.exp(-((r / 0.3) ** 2)))
    p.fill(r < 0.08, (1.0, 0.96, 0.8))


def _shelf(p: Paint):
    body = d.rect(p.u, p.v, 0.1, 0.0, 0.9, 0.8)
    p.alpha = body
    p.fill(body, (0.4, 0.27, 0.16), height=1.0)
    for k in range(4):
        row = d.rect(p.u, p.v, 0.14, 0.04 + 0.19 * k, 0.86, 0.2 + 0.19 * k)
        book = np.floor(p.u * 40)
        colour = 0.35 + 0.6 * d.cell_random(book * 5 + k, p.seed)
        p.fill(row, (0.7, 0.3, 0.25), height=0.5, tone=colour)


# --------------------------------------------------------------------------- bit masks


def _mask(shape: Callable[[np.ndarray, np.ndarray], np.ndarray]):
    def paint(p: Paint):
        p.alpha = shape(p.u, p.v)
        p.fill(np.ones_like(p.alpha), (1.0, 1.0, 1.0))

    return paint


# --------------------------------------------------------------------------- the catalogue


@dataclass(frozen=True)
class TileSpec:
    name: str
    label: str
    paint: Callable[[Paint], None]
    base: tuple[float, float, float] = (0.5, 0.5, 0.5)


def _spec(name, label, paint, base=(0.5, 0.5, 0.5)):
    return TileSpec(name, label, paint, base)


BRICK_RED, BRICK_YELLOW, BRICK_DARK = (0.58, 0.25, 0.18), (0.78, 0.66, 0.42), (0.36, 0.2, 0.16)
STONE, PLASTER, CONCRETE = (0.74, 0.7, 0.62), (0.86, 0.8, 0.68), (0.6, 0.6, 0.58)
WHITE_FRAME, DARK_FRAME, GREEN = (0.92, 0.92, 0.9), (0.18, 0.18, 0.2), (0.2, 0.35, 0.25)

TILES: tuple[TileSpec, ...] = (
    _spec("wall1", "wall", lambda p: _masonry(p, 16, 4, (0.75, 0.73, 0.68), BRICK_RED)),
    _spec("wall2", "wall", lambda p: _render_plaster(p, PLASTER)),
    _spec("wall3", "wall", lambda p: _masonry(p, 4, 2, (0.6, 0.58, 0.52), STONE, spread=0.1, mortar_width=0.03)),
    _spec("wall4", "wall", lambda p: _panels(p, CONCRETE)),
    _spec("brick_yellow", "wall", lambda p: _masonry(p, 16, 4, (0.6, 0.58, 0.55), BRICK_YELLOW)),
    _spec("brick_dark", "wall", lambda p: _masonry(p, 16, 4, (0.5, 0.5, 0.48), BRICK_DARK)),
    _spec("plaster_white", "wall", lambda p: _render_plaster(p, (0.93, 0.92, 0.88))),
    _spec("plaster_ochre", "wall", lambda p: _render_plaster(p, (0.85, 0.64, 0.38))),
    _spec("stone_ashlar", "wall", lambda p: _masonry(p, 3, 1, (0.55, 0.52, 0.46), (0.68, 0.64, 0.56), 0.12, 0.03)),
    _spec("concrete", "wall", lambda p: _render_plaster(p, CONCRETE, cells=3)),
    _spec("roof_tiles", "roof", _roof),
    _spec("window1", "window", lambda p: _window(p, WHITE_FRAME, (2, 1))),
    _spec("window2", "window", lambda p: _window(p, WHITE_FRAME, (2, 3))),
    _spec("window3", "window", lambda p: _window(p, WHITE_FRAME, (2, 2), "arch")),
    _spec("window4", "window", lambda p: _window(p, DARK_FRAME, (1, 1), border=0.05)),
    _spec("window_shutters", "window", lambda p: _window(p, WHITE_FRAME, (2, 2), shutters=GREEN)),
    _spec("window_round", "window", lambda p: _window(p, WHITE_FRAME, (2, 2), "round", border=0.1)),
    _spec("window_arch_dark", "window", lambda p: _window(p, DARK_FRAME, (1, 3), "arch", border=0.06)),
    _spec("window_office", "window", lambda p: _window(p, (0.55, 0.58, 0.6), (1, 1), border=0.03)),
    _spec("frame1", "window", lambda p: _window(p, WHITE_FRAME, (2, 2), open_glass=True)),
    _spec("frame_arch", "window", lambda p: _window(p, (0.3, 0.22, 0.16), (2, 3), "arch", open_glass=True)),
    _spec("glass", "window", lambda p: _glass(p, np.ones_like(p.alpha), tint=(0.2, 0.3, 0.36))),
    _spec("door1", "door", lambda p: _door(p, (0.42, 0.22, 0.12))),
    _spec("door2", "door", lambda p: _door(p, (0.2, 0.22, 0.25), glass_panel=True)),
    _spec("door_arched", "door", lambda p: _door(p, (0.3, 0.18, 0.1), arch=True)),
    _spec("cornice1", "cornice", lambda p: _cornice(p, (0.85, 0.83, 0.78))),
    _spec("cornice2", "cornice", lambda p: _cornice(p, (0.7, 0.66, 0.58), ((0, 0.5, 0.6), (0.5, 1.0, 1.0)))),
    _spec("sill", "cornice", lambda p: _cornice(p, (0.8, 0.78, 0.74), ((0, 0.4, 0.5), (0.4, 1.0, 1.0)))),
    _spec("balcony_rail1", "balcony", lambda p: _rail(p, (0.12, 0.12, 0.13))),
    _spec("balcony_rail2", "balcony", lambda p: _rail(p, (0.85, 0.85, 0.82), bars=16)),
    _spec("balcony_slab", "balcony", lambda p: _panels(p, (0.75, 0.74, 0.7), joints=1)),
    _spec("shop_front1", "shop", lambda p: _shop(p, (0.15, 0.15, 0.17), (0.6, 0.1, 0.1))),
    _spec("shop_front2", "shop", lambda p: _shop(p, (0.5, 0.35, 0.2), (0.1, 0.25, 0.5))),
    _spec("awning", "shop", lambda p: _awning(p, (0.7, 0.12, 0.12))),
    _spec("room_wall1", "room", lambda p: _wallpaper(p, (0.85, 0.78, 0.6), (0.3, 0.5, 0.7))),
    _spec("room_wall2", "room", lambda p: _wallpaper(p, (0.6, 0.72, 0.7), (0.8, 0.5, 0.3))),
    _spec("room_floor", "room", _floor),
    _spec("room_ceiling", "room", _ceiling),
    _spec("shelf", "room", _shelf),
    _spec("mask_arch", "none", _mask(lambda u, v: _arch_shape(u, v))),
    _spec("mask_round", "none", _mask(lambda u, v: d.ellipse(u, v, 0.5, 0.5, 0.5, 0.5))),
    _spec("mask_inset", "none", _mask(lambda u, v: d.rect(u, v, 0.1, 0.1, 0.9, 0.9))),
    _spec("mask_lancet", "none", _mask(lambda u, v: (v < 0.6) | (np.abs(u - 0.5) < 0.5 * (1 - (v - 0.6) / 0.4)))),
)

TILE_INDEX = {spec.name: i for i, spec in enumerate(TILES)}


@dataclass(frozen=True)
class TileArray:
    """Pixels of every tile: `layers` is (3 * tiles, size, size, 4) uint8, row 0 at the bottom."""

    size: int
    layers: np.ndarray
    labels: np.ndarray  # per tile, index into LABELS

    def plane(self, tile: int, usage: int) -> np.ndarray:
        return self.layers[3 * tile + usage - 1]


def tile_labels() -> np.ndarray:
    return np.array([LABELS.index(spec.label) for spec in TILES], np.int32)


@lru_cache(maxsize=4)
def tile_array(size: int = 128) -> TileArray:
    """All tiles painted at size x size texels (deterministic)."""
    layers = np.empty((3 * len(TILES), size, size, 4), np.uint8)
    for index, spec in enumerate(TILES):
        p = Paint.blank(size, spec.base, seed=1000 + index)
        spec.paint(p)
        alpha = np.where(p.alpha, 255, 0).astype(np.uint8)
        layers[3 * index] = d.to_rgba8(p.rgb, p.alpha)
        layers[3 * index + 1] = _normal_map(p.height, alpha)
        spec_plane = np.stack([p.spec, np.full_like(p.spec, 0.25), p.glass.astype(np.float32)], axis=-1)
        layers[3 * index + 2] = d.to_rgba8(spec_plane, p.alpha)
    return TileArray(size, d.frozen(layers), d.frozen(tile_labels()))


def _normal_map(height: np.ndarray, alpha: np.ndarray, strength: float = 2.5) -> np.ndarray:
    """Tangent-space normals from a height field (wrapping, so tiled walls stay seamless)."""
    dhdu = (np.roll(height, -1, axis=1) - np.roll(height, 1, axis=1)) * 0.5 * strength
    dhdv = (np.roll(height, -1, axis=0) - np.roll(height, 1, axis=0)) * 0.5 * strength
    n = np.stack([-dhdu, -dhdv, np.ones_like(height)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    rgb = np.clip((n * 0.5 + 0.5) * 255 + 0.5, 0, 255).astype(np.uint8)
    return np.concatenate([rgb, alpha[..., None]], axis=-1)
