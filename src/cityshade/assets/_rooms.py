"""Room textures for interior mapping: ceiling, floor and two wall orientations per room.

Each texture covers exactly one face of one room (paper §2.2): on walls u runs
along the wall and v from the floor (0) to the ceiling (1); on floors and
ceilings u, v span the room. Variants are different kinds of room (paper §4.2),
chosen from a table of styles; the seed varies colours and details.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

import numpy as np

from . import _draw as d
from ._curtain import fold_shade

FACES = ("ceiling", "floor", "wall_x", "wall_z")

SKIRTING_TOP = 0.045
CEILING_BAND = 0.955

BOOK_COLOURS = np.array(
    [
        (0.55, 0.12, 0.10),
        (0.12, 0.20, 0.42),
        (0.16, 0.36, 0.20),
        (0.78, 0.60, 0.22),
        (0.40, 0.24, 0.14),
        (0.86, 0.82, 0.70),
        (0.12, 0.12, 0.13),
        (0.62, 0.30, 0.45),
    ],
    np.float32,
)
PRODUCT_COLOURS = np.array(
    [
        (0.90, 0.20, 0.15),
        (0.95, 0.75, 0.10),
        (0.15, 0.55, 0.85),
        (0.20, 0.70, 0.35),
        (0.95, 0.95, 0.92),
        (0.85, 0.40, 0.65),
        (0.98, 0.55, 0.15),
        (0.35, 0.30, 0.75),
    ],
    np.float32,
)


class Face:
    """One face being painted: its image, texel coordinates and random source."""

    def __init__(self, size: int, base: np.ndarray, rng: np.random.Generator, seed: int):
        self.u, self.v = d.uv_grid(size)
        self.img = d.canvas(size, size, base)
        self.rng = rng
        self.seed = seed

    def fill(self, mask, colour, shade=None):
        d.paint(self.img, mask, colour, shade)

    def rect(self, u0, v0, u1, v1):
        return d.rect(self.u, self.v, u0, v0, u1, v1)

    def frame(self, u0, v0, u1, v1, width, colour):
        """Paint a rectangular border of `width` around [u0,u1]x[v0,v1]."""
        outer = self.rect(u0 - width, v0 - width, u1 + width, v1 + width)
        self.fill(outer & ~self.rect(u0, v0, u1, v1), colour)


# --------------------------------------------------------------------------- floors


def carpet(f: Face):
    f.img *= (0.86 + 0.2 * d.fbm(f.u, f.v, 32, 2, f.seed))[..., None]


def planks(f: Face, plank_width=0.1):
    column = np.floor(f.u / plank_width)
    length = 0.45
    row = np.floor(f.v / length + d.cell_random(column, f.seed) * 3)
    tone = 0.82 + 0.3 * d.cell_random(column * 31 + row, f.seed, 1)
    grain = 0.9 + 0.15 * d.fbm(f.u * 0.5, f.v * 4, 16, 3, f.seed + 5)
    f.img *= (tone * grain)[..., None]
    gap = ((f.u / plank_width) % 1 < 0.05) | ((f.v / length + d.cell_random(column, f.seed) * 3) % 1 < 0.012)
    d.shade(f.img, 0.55, gap)


def tiles(f: Face, other, count=8, grout=(0.75, 0.75, 0.72)):
    cu, cv = np.floor(f.u * count), np.floor(f.v * count)
    f.fill(((cu + cv) % 2) == 1, other)
    f.img *= (0.95 + 0.08 * d.fbm(f.u, f.v, 16, 2, f.seed))[..., None]
    line = ((f.u * count) % 1 < 0.05) | ((f.v * count) % 1 < 0.05)
    f.fill(line, grout)


def concrete(f: Face):
    f.img *= (0.8 + 0.3 * d.fbm(f.u, f.v, 6, 4, f.seed))[..., None]


def rug(f: Face, colour, border):
    inner = f.rect(0.28, 0.3, 0.72, 0.7)
    f.fill(f.rect(0.25, 0.27, 0.75, 0.73), border)
    f.fill(inner, colour, 0.9 + 0.15 * np.cos(f.u * 60) * np.cos(f.v * 60))


# --------------------------------------------------------------------------- ceilings


def ceiling_panels(f: Face, lights=((0.2, 0.45), (0.55, 0.8))):
    line = ((f.u * 4) % 1 < 0.02) | ((f.v * 4) % 1 < 0.02)
    d.shade(f.img, 0.82, line)
    for v0, v1 in lights:
        f.frame(0.27, v0 + 0.08, 0.73, v1 - 0.08, 0.02, (0.7, 0.7, 0.72))
        f.fill(f.rect(0.27, v0 + 0.08, 0.73, v1 - 0.08), (1.0, 1.0, 0.97))


def ceiling_lamp(f: Face, radius=0.09, rim=(0.85, 0.8, 0.7), glow=0.3):
    r = np.hypot(f.u - 0.5, f.v - 0.5)
    f.img *= (1 + glow * np.exp(-((r / 0.25) ** 2)))[..., None]
    f.fill(r < radius * 1.25, rim)
    f.fill(r < radius, (1.0, 0.97, 0.85))


def beams(f: Face, wood=(0.36, 0.24, 0.15)):
    beam = (f.v * 4 + 0.5) % 1 < 0.16
    f.fill(beam, wood, 0.85 + 0.25 * d.fbm(f.u * 0.3, f.v * 3, 16, 2, f.seed))


# --------------------------------------------------------------------------- wall bases


def plaster(f: Face):
    f.img *= (0.97 + 0.05 * d.fbm(f.u, f.v, 8, 3, f.seed))[..., None]


def wallpaper(f: Face, stripe, stripes=12):
    phase = (f.u * stripes) % 1
    f.fill((phase > 0.35) & (phase < 0.65), stripe)
    dots = ((f.u * stripes) % 1 - 0.5) ** 2 + ((f.v * stripes * 0.5) % 1 - 0.5) ** 2 < 0.02
    f.fill(dots & ~((phase > 0.35) & (phase < 0.65)), stripe)


def two_tone(f: Face, lower, split=0.42):
    f.fill(f.v < split, lower)
    f.fill(np.abs(f.v - split) < 0.006, np.asarray(lower) * 0.7)


def brick(f: Face, mortar=(0.62, 0.58, 0.52), courses=14, bricks=6):
    row = np.floor(f.v * courses)
    x = f.u * bricks + 0.5 * (row % 2)
    tone = 0.8 + 0.35 * d.cell_random(np.floor(x) * 53 + row, f.seed, 2)
    f.img *= (tone * (0.9 + 0.15 * d.fbm(f.u, f.v, 16, 2, f.seed)))[..., None]
    joint = ((f.v * courses) % 1 < 0.12) | (x % 1 < 0.04)
    f.fill(joint, mortar)


# --------------------------------------------------------------------------- wall furniture


def door(f: Face, colour, centre=0.5, frame_colour=(0.92, 0.9, 0.86)):
    u0, u1, top = centre - 0.11, centre + 0.11, 0.8
    f.frame(u0, 0.0, u1, top, 0.018, frame_colour)
    f.fill(f.rect(u0, 0.0, u1, top), colour)
    for v0, v1 in ((0.08, 0.36), (0.44, 0.74)):
        f.fill(f.rect(u0 + 0.03, v0, u1 - 0.03, v1), colour, np.full_like(f.u, 0.86))
    f.fill(d.ellipse(f.u, f.v, u1 - 0.03, 0.4, 0.012, 0.012), (0.8, 0.75, 0.55))


def window(f: Face, colour, u0=0.25, u1=0.75, curtains=None):
    v0, v1 = 0.32, 0.84
    f.frame(u0, v0, u1, v1, 0.02, colour)
    sky = np.stack([0.3 + 0.2 * f.v, 0.4 + 0.25 * f.v, 0.55 + 0.3 * f.v], -1)
    glass = f.rect(u0, v0, u1, v1)
    f.img[glass] = sky[glass]
    f.fill(glass & (np.abs(f.u - (u0 + u1) / 2) < 0.008), colour)
    f.fill(glass & (np.abs(f.v - 0.64) < 0.008), colour)
    f.fill(f.rect(u0 - 0.04, v0 - 0.035, u1 + 0.04, v0 - 0.01), np.asarray(colour) * 0.9)
    if curtains is not None:
        for c0, c1 in ((u0 - 0.09, u0 + 0.04), (u1 - 0.04, u1 + 0.09)):
            f.fill(f.rect(c0, v0 - 0.08, c1, v1 + 0.08), curtains, fold_shade((f.u - c0) / (c1 - c0), 2))


def radiator(f: Face, colour, u0=0.32, u1=0.68):
    area = f.rect(u0, 0.1, u1, 0.26)
    f.fill(area, colour, 0.8 + 0.2 * np.cos(f.u * 2 * np.pi * 60) ** 2)


def whiteboard(f: Face, colour, u0=0.15, u1=0.7):
    v0, v1 = 0.42, 0.82
    f.frame(u0, v0, u1, v1, 0.012, (0.7, 0.72, 0.75))
    f.fill(f.rect(u0, v0, u1, v1), colour)
    for i, ink in enumerate([(0.15, 0.25, 0.7), (0.75, 0.15, 0.15), (0.1, 0.1, 0.1)]):
        base = v1 - 0.08 - 0.1 * i
        length = u0 + (u1 - u0) * (0.4 + 0.5 * f.rng.random())
        wave = base + 0.015 * np.sin(f.u * (90 + 40 * i))
        f.fill(f.rect(u0 + 0.04, v0, length, v1) & (np.abs(f.v - wave) < 0.005), ink)


def desk(f: Face, colour, u0=0.1, u1=0.8):
    f.fill(f.rect(u0, 0.33, u1, 0.37), colour)
    for leg in (u0 + 0.01, u1 - 0.04):
        f.fill(f.rect(leg, 0.0, leg + 0.03, 0.33), np.asarray(colour) * 0.7)
    f.fill(f.rect(u0 + 0.15, 0.41, u0 + 0.37, 0.55), (0.08, 0.09, 0.1))
    f.fill(f.rect(u0 + 0.16, 0.42, u0 + 0.36, 0.54), (0.3, 0.45, 0.65))
    f.fill(f.rect(u0 + 0.25, 0.37, u0 + 0.27, 0.41), (0.2, 0.2, 0.2))


def pictures(f: Face, colour, count=2, v0=0.5, v1=0.75, u0=0.15, u1=0.85):
    width = (u1 - u0) / count
    for i in range(count):
        a, b = u0 + i * width + 0.15 * width, u0 + (i + 1) * width - 0.15 * width
        f.frame(a, v0, b, v1, 0.014, colour)
        sky, land, sun = f.rng.random((3, 3)) * 0.6 + 0.3
        horizon = v0 + (v1 - v0) * (0.3 + 0.3 * f.rng.random())
        f.fill(f.rect(a, v0, b, v1), sky)
        f.fill(f.rect(a, v0, b, horizon), land * 0.7)
        f.fill(d.ellipse(f.u, f.v, (a + b) / 2, horizon + 0.05, 0.025, 0.025) & f.rect(a, horizon, b, v1), sun)


def shelf_unit(f: Face, colour, u0=0.05, u1=0.95, v1=0.92, rows=5, item=0.02, colours=BOOK_COLOURS, salt=0):
    """A shelving case full of items (books or products) with per-slot random colour and height."""
    f.fill(f.rect(u0, 0.0, u1, v1), colour)
    inner = f.rect(u0 + 0.02, 0.06, u1 - 0.02, v1 - 0.03)
    row_height = (v1 - 0.09) / rows
    row = np.floor((f.v - 0.06) / row_height)
    local = (f.v - 0.06) / row_height - row
    slot = np.floor((f.u - u0) / item) + 997 * row
    pick = d.cell_random(slot, f.seed, 3 + salt)
    height = 0.55 + 0.35 * d.cell_random(slot, f.seed, 4 + salt)
    back = inner & (local >= 0.08)
    f.fill(back, np.asarray(colour) * 0.45)
    item_mask = back & (local < height) & (pick > 0.08) & (((f.u - u0) / item) % 1 > 0.08)
    idx = (pick * len(colours)).astype(int) % len(colours)
    f.img[item_mask] = colours[idx[item_mask]] * (0.85 + 0.2 * local[item_mask, None])


def counter(f: Face, colour, top=(0.3, 0.3, 0.32), u0=0.0, u1=1.0, wall_units=True):
    """Base cabinets with a worktop; with `wall_units`, a tiled splashback and upper cabinets."""
    c = np.asarray(colour)
    doors = (f.u - u0) * 6 / (u1 - u0) % 1
    units = [(0.04, 0.38)] + ([(0.62, 0.88)] if wall_units else [])
    for v0, v1 in units:
        f.fill(f.rect(u0, v0, u1, v1), c)
        f.fill(f.rect(u0, v0, u1, v1) & (doors < 0.015), c * 0.6)
        f.fill(f.rect(u0, v1 - 0.08, u1, v1 - 0.04) & (doors > 0.85) & (doors < 0.9), (0.8, 0.8, 0.82))
    f.fill(f.rect(u0, 0.0, u1, 0.04), c * 0.4)
    f.fill(f.rect(u0 - 0.01, 0.38, u1 + 0.01, 0.42), top)
    if wall_units:
        f.fill(f.rect(u0, 0.42, u1, 0.6) & (((f.u * 20) % 1 < 0.06) | ((f.v * 40) % 1 < 0.08)), (0.75, 0.75, 0.72))


def fridge(f: Face, colour, u0=0.78, u1=0.95):
    f.fill(f.rect(u0, 0.0, u1, 0.86), colour, 0.92 + 0.08 * (f.u - u0) / (u1 - u0))
    f.fill(f.rect(u0, 0.55, u1, 0.565), np.asarray(colour) * 0.6)
    f.fill(f.rect(u0 + 0.01, 0.4, u0 + 0.02, 0.52) | f.rect(u0 + 0.01, 0.6, u0 + 0.02, 0.72), (0.6, 0.6, 0.62))


def sofa(f: Face, colour, u0=0.2, u1=0.8):
    c = np.asarray(colour)
    f.fill(f.rect(u0 + 0.05, 0.12, u1 - 0.05, 0.42), c * 0.85)
    f.fill(f.rect(u0, 0.04, u1, 0.22), c)
    f.fill(f.rect(u0, 0.04, u0 + 0.06, 0.3) | f.rect(u1 - 0.06, 0.04, u1, 0.3), c * 0.95)
    f.fill(f.rect(u0 + 0.02, 0.0, u0 + 0.04, 0.04) | f.rect(u1 - 0.04, 0.0, u1 - 0.02, 0.04), (0.2, 0.15, 0.1))
    cushion = f.rect(u0 + 0.08, 0.22, u1 - 0.08, 0.4) & ((((f.u - u0 - 0.08) / (u1 - u0 - 0.16)) * 3) % 1 < 0.96)
    f.fill(cushion, c * 1.1, 0.9 + 0.1 * np.sin((f.v - 0.22) / 0.18 * np.pi))


def bed(f: Face, colour, u0=0.2, u1=0.8, wood=(0.45, 0.3, 0.2)):
    f.fill(f.rect(u0, 0.0, u1, 0.55), wood)
    f.fill(f.rect(u0 + 0.02, 0.2, u1 - 0.02, 0.3), (0.92, 0.92, 0.9))
    for a, b in ((u0 + 0.05, 0.48), (0.52, u1 - 0.05)):
        f.fill(d.ellipse(f.u, f.v, (a + b) / 2, 0.34, (b - a) / 2, 0.06), (0.95, 0.95, 0.93))
    f.fill(f.rect(u0 - 0.02, 0.0, u1 + 0.02, 0.26), colour, 0.9 + 0.1 * np.cos(f.u * 80))


def wardrobe(f: Face, colour, u0=0.06, u1=0.42):
    f.fill(f.rect(u0, 0.0, u1, 0.88), colour, 0.9 + 0.15 * d.fbm(f.u, f.v * 0.2, 16, 2, f.seed))
    mid = (u0 + u1) / 2
    f.fill(f.rect(mid - 0.004, 0.03, mid + 0.004, 0.86), np.asarray(colour) * 0.5)
    f.fill(f.rect(mid - 0.03, 0.42, mid - 0.02, 0.52) | f.rect(mid + 0.02, 0.42, mid + 0.03, 0.52), (0.8, 0.75, 0.5))


def stairs(f: Face, colour, steps=10, u0=0.08, u1=0.92, rail=(0.25, 0.25, 0.28)):
    run = (u1 - u0) / steps
    step = np.floor((f.u - u0) / run)
    tread = (step + 1) * 0.085
    body = f.rect(u0, 0.0, u1, 1.0) & (f.v < tread)
    f.fill(body, colour, 0.8 + 0.2 * f.v)
    f.fill(body & (f.v > tread - 0.012), np.asarray(colour) * 0.6)
    slope = (f.u - u0) / run * 0.085 + 0.3
    f.fill(f.rect(u0, 0.0, u1, 1.0) & (np.abs(f.v - slope) < 0.008), rail)
    posts = f.rect(u0, 0.0, u1, 1.0) & (((f.u - u0) / run) % 2 < 0.12) & (f.v > tread) & (f.v < slope)
    f.fill(posts, rail)


def posters(f: Face, count=3):
    for i in range(count):
        a = 0.12 + i * 0.28
        tint = PRODUCT_COLOURS[int(f.rng.integers(len(PRODUCT_COLOURS)))]
        f.fill(f.rect(a, 0.5, a + 0.18, 0.82), tint)
        f.fill(f.rect(a + 0.02, 0.72, a + 0.16, 0.78), (0.98, 0.98, 0.95))
        f.fill(d.ellipse(f.u, f.v, a + 0.09, 0.6, 0.05, 0.06), np.asarray(tint) * 0.5 + 0.4)


# --------------------------------------------------------------------------- room finishing


def finish_wall(f: Face, skirting):
    """Skirting board, dark ceiling band and corner shading, so room edges read clearly."""
    wall_colour = f.img[int(0.93 * f.img.shape[0]), 1].copy()
    f.fill(f.v < SKIRTING_TOP, skirting)
    f.fill(np.abs(f.v - SKIRTING_TOP) < 0.006, np.asarray(skirting) * 0.75)
    f.fill(f.v > CEILING_BAND, wall_colour * 0.55)
    corner = np.minimum(f.u, 1 - f.u)
    light = 0.86 + 0.14 * f.v
    light = light * (1 - 0.3 * np.exp(-corner / 0.03)) * (1 - 0.2 * np.exp(-(1 - f.v) / 0.04))
    d.shade(f.img, light)


def finish_flat(f: Face, centre_light):
    edge = np.minimum(np.minimum(f.u, 1 - f.u), np.minimum(f.v, 1 - f.v))
    r2 = (f.u - 0.5) ** 2 + (f.v - 0.5) ** 2
    d.shade(f.img, (1 - centre_light + centre_light * np.exp(-r2 / 0.15)) * (1 - 0.35 * np.exp(-edge / 0.03)))


# --------------------------------------------------------------------------- the room table

Step = Callable[[Face], None]


@dataclass(frozen=True)
class RoomStyle:
    """What one kind of room is made of: a base colour and painting steps per face."""

    name: str
    ceiling: tuple
    floor: tuple
    wall: tuple
    wall_x: tuple[Step, ...]
    wall_z: tuple[Step, ...]
    skirting: tuple = (0.9, 0.88, 0.84)


def _step(fn, *args, **kwargs) -> Step:
    """A painting step with its arguments bound; called with the face only."""
    return lambda face: fn(face, *args, **kwargs)


WHITE_CEILING = (0.9, 0.9, 0.88)

ROOM_STYLES: tuple[RoomStyle, ...] = (
    RoomStyle(
        "office",
        ceiling=(WHITE_CEILING, ceiling_panels),
        floor=((0.42, 0.45, 0.5), carpet),
        wall=((0.82, 0.83, 0.82), plaster),
        wall_x=(_step(whiteboard, (0.97, 0.97, 0.97)), _step(desk, (0.62, 0.5, 0.38), u0=0.15, u1=0.85)),
        wall_z=(
            _step(window, (0.85, 0.85, 0.86), u0=0.12, u1=0.52),
            _step(radiator, (0.9, 0.9, 0.9), u0=0.17, u1=0.47),
            _step(door, (0.55, 0.42, 0.3), centre=0.76),
        ),
        skirting=(0.3, 0.3, 0.32),
    ),
    RoomStyle(
        "living",
        ceiling=((0.95, 0.92, 0.86), _step(ceiling_lamp, radius=0.08, rim=(0.75, 0.6, 0.4))),
        floor=((0.6, 0.42, 0.26), planks, _step(rug, (0.6, 0.2, 0.18), (0.85, 0.75, 0.5))),
        wall=((0.86, 0.72, 0.5), _step(wallpaper, (0.8, 0.62, 0.42))),
        wall_x=(
            _step(door, (0.92, 0.9, 0.86), centre=0.25),
            _step(pictures, (0.35, 0.22, 0.12), count=1, u0=0.5, u1=0.9),
        ),
        wall_z=(_step(sofa, (0.3, 0.42, 0.55)), _step(pictures, (0.15, 0.12, 0.1), count=3, v0=0.55, v1=0.78)),
        skirting=(0.95, 0.94, 0.9),
    ),
    RoomStyle(
        "kitchen",
        ceiling=(WHITE_CEILING, _step(ceiling_lamp, radius=0.1)),
        floor=((0.9, 0.9, 0.88), _step(tiles, (0.2, 0.22, 0.25), count=8)),
        wall=((0.78, 0.86, 0.8), plaster),
        wall_x=(_step(counter, (0.35, 0.52, 0.48), u1=0.74), _step(fridge, (0.9, 0.9, 0.9))),
        wall_z=(
            _step(window, (0.95, 0.95, 0.95), u0=0.2, u1=0.55, curtains=(0.85, 0.3, 0.25)),
            _step(door, (0.7, 0.78, 0.75), centre=0.8),
        ),
    ),
    RoomStyle(
        "bedroom",
        ceiling=((0.93, 0.92, 0.95), _step(ceiling_lamp, radius=0.06, rim=(0.9, 0.7, 0.75), glow=0.2)),
        floor=((0.72, 0.6, 0.58), carpet),
        wall=((0.62, 0.7, 0.82), plaster),
        wall_x=(
            _step(bed, (0.75, 0.35, 0.4)),
            _step(pictures, (0.9, 0.9, 0.9), count=1, v0=0.62, v1=0.82, u0=0.3, u1=0.7),
        ),
        wall_z=(_step(wardrobe, (0.68, 0.52, 0.36)), _step(door, (0.95, 0.95, 0.95), centre=0.75)),
    ),
    RoomStyle(
        "shop",
        ceiling=((0.95, 0.95, 0.95), _step(ceiling_panels, lights=((0.05, 0.35), (0.35, 0.65), (0.65, 0.95)))),
        floor=((0.85, 0.84, 0.8), _step(tiles, (0.78, 0.77, 0.72), count=5, grout=(0.6, 0.6, 0.58))),
        wall=((0.96, 0.96, 0.95), plaster),
        wall_x=(_step(shelf_unit, (0.85, 0.85, 0.87), rows=4, item=0.045, colours=PRODUCT_COLOURS),),
        wall_z=(posters, _step(counter, (0.2, 0.35, 0.6), u0=0.1, u1=0.9, wall_units=False)),
        skirting=(0.25, 0.25, 0.27),
    ),
    RoomStyle(
        "stairwell",
        ceiling=((0.85, 0.85, 0.83), _step(ceiling_lamp, radius=0.05, rim=(0.6, 0.6, 0.6), glow=0.15)),
        floor=((0.55, 0.55, 0.53), concrete),
        wall=((0.9, 0.88, 0.8), _step(two_tone, lower=(0.35, 0.5, 0.45))),
        wall_x=(_step(stairs, (0.6, 0.6, 0.58)),),
        wall_z=(_step(door, (0.55, 0.2, 0.15), centre=0.5),),
        skirting=(0.25, 0.3, 0.28),
    ),
    RoomStyle(
        "library",
        ceiling=((0.82, 0.76, 0.65), _step(ceiling_lamp, radius=0.07, rim=(0.45, 0.35, 0.2), glow=0.4), beams),
        floor=((0.42, 0.27, 0.16), _step(planks, plank_width=0.07), _step(rug, (0.2, 0.3, 0.22), (0.7, 0.6, 0.35))),
        wall=((0.2, 0.35, 0.27), plaster),
        wall_x=(_step(shelf_unit, (0.38, 0.24, 0.14)),),
        wall_z=(
            _step(shelf_unit, (0.38, 0.24, 0.14), u0=0.04, u1=0.55, salt=7),
            _step(pictures, (0.75, 0.6, 0.25), count=1, u0=0.6, u1=0.98, v0=0.45, v1=0.75),
        ),
        skirting=(0.3, 0.2, 0.12),
    ),
    RoomStyle(
        "loft",
        ceiling=((0.75, 0.74, 0.72), beams, _step(ceiling_lamp, radius=0.05, rim=(0.1, 0.1, 0.1), glow=0.35)),
        floor=((0.5, 0.5, 0.49), concrete),
        wall=((0.62, 0.3, 0.2), brick),
        wall_x=(_step(window, (0.15, 0.15, 0.16), u0=0.1, u1=0.9),),
        wall_z=(
            _step(pictures, (0.1, 0.1, 0.1), count=2, v0=0.45, v1=0.72),
            _step(sofa, (0.3, 0.36, 0.32), u0=0.25, u1=0.75),
        ),
        skirting=(0.2, 0.2, 0.2),
    ),
)


def _paint_face(size: int, spec: tuple, rng: np.random.Generator, seed: int) -> Face:
    """A face painted from a (base colour, step, step, ...) entry of a RoomStyle."""
    base, *steps = spec
    f = Face(size, np.asarray(base, np.float32), rng, seed)
    for step in steps:
        step(f)
    return f


def _render_room(style: RoomStyle, size: int, seed: int, variant: int) -> dict[str, np.ndarray]:
    jitter = 1 + 0.06 * np.random.default_rng([seed, variant, 99]).standard_normal(3).astype(np.float32)
    faces = {}
    for index, face in enumerate(FACES):
        rng = np.random.default_rng([seed, variant, index])
        noise_seed = seed * 7919 + variant * 131 + index
        if face in ("ceiling", "floor"):
            f = _paint_face(size, getattr(style, face), rng, noise_seed)
            finish_flat(f, 0.3 if face == "floor" else 0.1)
        else:
            f = _paint_face(size, style.wall, rng, noise_seed)
            for step in getattr(style, face):
                step(f)
            finish_wall(f, style.skirting)
        faces[face] = d.to_rgba8(f.img * jitter)
    return faces


@lru_cache(maxsize=8)
def _room_stack(size: int, variants: int, seed: int) -> dict[str, np.ndarray]:
    rooms = [_render_room(ROOM_STYLES[k % len(ROOM_STYLES)], size, seed, k) for k in range(variants)]
    return {face: d.frozen(np.stack([room[face] for room in rooms])) for face in FACES}


def room_textures(size: int = 256, variants: int = 8, seed: int = 0) -> dict[str, np.ndarray]:
    """Textures of `variants` different rooms, one per face kind.

    Returns {"ceiling", "floor", "wall_x", "wall_z"} -> (variants, size, size, 4) uint8
    sRGB RGBA, alpha 255, row 0 = v = 0 (the floor line on walls). Variant k is the
    room style ROOM_STYLES[k % len(ROOM_STYLES)] (office, living, kitchen, bedroom,
    shop, stairwell, library, loft); the seed varies colours and details. The arrays
    are read-only (they are cached); copy them to modify.
    """
    if size < 16 or variants < 1:
        raise ValueError(f"room_textures needs size >= 16 and variants >= 1, got size={size}, variants={variants}")
    return dict(_room_stack(int(size), int(variants), int(seed)))
