"""Animated furniture-plane sprites (paper §2.4): things seen through a window.

Each sprite stands on the floor line (v = 0) and v = 1 is the ceiling, so a
person is about 0.6 of the room height. Alpha is hard (0 or 255) for an alpha
test; frames loop.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from . import _draw as d


class Sprite:
    """One frame being drawn: colour, coverage and texel coordinates."""

    def __init__(self, size: int):
        self.u, self.v = d.uv_grid(size)
        self.img = d.canvas(size, size, (0, 0, 0))
        self.alpha = np.zeros((size, size), bool)

    def fill(self, mask, colour, shade=None):
        d.paint(self.img, mask, colour, shade)
        self.alpha |= mask

    def round_shade(self, cu, cv, ru, rv):
        """Light from the upper left on a rounded body centred at (cu, cv)."""
        du, dv = (self.u - cu) / ru, (self.v - cv) / rv
        return np.clip(1.0 - 0.25 * (du * du + dv * dv) - 0.2 * du + 0.12 * dv, 0.45, 1.15)

    def ellipse(self, cu, cv, ru, rv, colour):
        self.fill(d.ellipse(self.u, self.v, cu, cv, ru, rv), colour, self.round_shade(cu, cv, ru, rv))

    def box(self, u0, v0, u1, v1, colour):
        cu, cv = (u0 + u1) / 2, (v0 + v1) / 2
        self.fill(
            d.rect(self.u, self.v, u0, v0, u1, v1), colour, self.round_shade(cu, cv, (u1 - u0) * 1.5, (v1 - v0) * 1.5)
        )

    def limb(self, p0, p1, radius, colour):
        self.fill(d.capsule(self.u, self.v, p0, p1, radius), colour, self.round_shade(*p0, 0.3, 0.3))


SKIN = (0.85, 0.66, 0.52)
HAIR = (0.25, 0.17, 0.1)


def person_waving(s: Sprite, frame: int, frames: int, rng):
    shirt, trousers = rng.random(3) * 0.5 + 0.25, (0.2, 0.22, 0.3)
    c = 0.5
    s.limb((c - 0.035, 0.02), (c - 0.03, 0.3), 0.03, trousers)
    s.limb((c + 0.035, 0.02), (c + 0.03, 0.3), 0.03, trousers)
    s.box(c - 0.045, 0.0, c - 0.005, 0.025, (0.1, 0.08, 0.07))
    s.box(c + 0.005, 0.0, c + 0.045, 0.025, (0.1, 0.08, 0.07))
    s.limb((c, 0.32), (c, 0.47), 0.07, shirt)
    s.limb((c - 0.07, 0.48), (c - 0.09, 0.3), 0.022, shirt)
    # The waving arm swings about the elbow, held up beside the head.
    phase = 2 * np.pi * frame / frames
    angle = np.pi / 2 + 0.55 * np.cos(phase)
    elbow = (c + 0.13, 0.5)
    hand = (elbow[0] + 0.13 * np.cos(angle), elbow[1] + 0.13 * np.sin(angle))
    s.limb((c + 0.06, 0.5), elbow, 0.022, shirt)
    s.limb(elbow, hand, 0.02, shirt)
    s.ellipse(hand[0], hand[1], 0.026, 0.026, SKIN)
    head = c + 0.012 * np.sin(phase)  # the head sways with the wave
    s.ellipse(head, 0.58, 0.045, 0.055, SKIN)
    s.fill(d.ellipse(s.u, s.v, head, 0.605, 0.047, 0.035) & (s.v > 0.595), HAIR)


def floor_lamp(s: Sprite, frame: int, frames: int, rng):
    c = 0.5
    s.ellipse(c, 0.015, 0.08, 0.015, (0.15, 0.15, 0.16))
    s.box(c - 0.008, 0.0, c + 0.008, 0.5, (0.3, 0.3, 0.32))
    flicker = (1.0, 0.5, 0.78, 0.3, 0.9, 0.6)[frame % 6]
    shade = d.trapezoid(s.u, s.v, c, 0.48, 0.64, 0.11, 0.06)
    glow = np.clip(flicker * (1.25 - 1.2 * np.abs(s.u - c)), 0, 1.2)
    s.fill(shade, (1.0, 0.8, 0.45), glow)
    s.fill(shade & (s.v < 0.49), np.array([1.0, 0.9, 0.6]) * flicker)


def sofa_reader(s: Sprite, frame: int, frames: int, rng):
    body = rng.random(3) * 0.4 + 0.2
    sofa = (0.55, 0.2, 0.18)
    s.box(0.12, 0.03, 0.88, 0.38, np.array(sofa) * 0.85)
    s.ellipse(0.5, 0.54, 0.07, 0.08, SKIN)
    s.fill(d.ellipse(s.u, s.v, 0.5, 0.575, 0.073, 0.06) & (s.v > 0.56), HAIR)
    s.limb((0.5, 0.25), (0.5, 0.42), 0.08, body)
    s.box(0.1, 0.03, 0.9, 0.2, sofa)
    s.box(0.08, 0.03, 0.17, 0.28, np.array(sofa) * 0.95)
    s.box(0.83, 0.03, 0.92, 0.28, np.array(sofa) * 0.95)
    s.box(0.12, 0.0, 0.15, 0.03, (0.2, 0.15, 0.1))
    s.box(0.85, 0.0, 0.88, 0.03, (0.2, 0.15, 0.1))
    # An open newspaper; its right page turns over to the left across the frames.
    paper = (0.92, 0.91, 0.86)
    s.box(0.36, 0.3, 0.5, 0.52, paper)
    turn = np.cos(np.pi * frame / max(frames - 1, 1))
    edge = 0.5 + 0.14 * turn
    lo, hi = min(0.5, edge), max(0.5, edge) + 0.004
    s.fill(d.rect(s.u, s.v, lo, 0.3, hi, 0.52), paper, np.full_like(s.u, 0.75 + 0.25 * abs(turn)))
    lines = d.rect(s.u, s.v, 0.38, 0.33, 0.48, 0.48) & ((s.v * 60) % 1 < 0.3)
    s.fill(lines & s.alpha, (0.4, 0.4, 0.4))
    s.limb((0.42, 0.36), (0.37, 0.4), 0.018, SKIN)
    s.limb((0.58, 0.36), (0.64, 0.4), 0.018, SKIN)


def potted_plant(s: Sprite, frame: int, frames: int, rng):
    c = 0.5
    phase = 2 * np.pi * frame / frames
    sway = 0.035 * np.cos(phase) + 0.012 * np.sin(phase)
    green = np.array([0.2, 0.5, 0.18])
    for i, (height, side) in enumerate(((0.42, -1), (0.36, 1), (0.33, -1), (0.45, 1), (0.28, 0))):
        tip = (c + side * 0.09 + sway * height / 0.4, height)
        s.limb((c, 0.12), tip, 0.006, green * 0.6)
        s.ellipse(tip[0], tip[1], 0.05, 0.022 + 0.005 * i, green * (0.85 + 0.06 * i))
    s.fill(d.trapezoid(s.u, s.v, c, 0.0, 0.14, 0.05, 0.07), (0.7, 0.38, 0.22), s.round_shade(c, 0.07, 0.1, 0.2))
    s.box(c - 0.075, 0.13, c + 0.075, 0.155, (0.62, 0.33, 0.2))


def tv_stand(s: Sprite, frame: int, frames: int, rng):
    screen = rng.random((frames, 3)) ** 0.7
    s.box(0.22, 0.0, 0.78, 0.2, (0.35, 0.25, 0.18))
    s.box(0.25, 0.04, 0.49, 0.16, (0.28, 0.2, 0.14))
    s.box(0.51, 0.04, 0.75, 0.16, (0.28, 0.2, 0.14))
    s.box(0.47, 0.2, 0.53, 0.24, (0.1, 0.1, 0.1))
    s.box(0.24, 0.24, 0.76, 0.56, (0.06, 0.06, 0.07))
    picture = d.rect(s.u, s.v, 0.26, 0.26, 0.74, 0.54)
    s.fill(picture, screen[frame], 0.7 + 0.3 * s.v / 0.56)
    s.fill(picture & d.ellipse(s.u, s.v, 0.4 + 0.2 * frame / frames, 0.38, 0.06, 0.08), 1 - screen[frame] * 0.6)


SPRITE_KINDS = (person_waving, floor_lamp, sofa_reader, potted_plant, tv_stand)


@lru_cache(maxsize=8)
def _sprites(size: int, kinds: int, frames: int, seed: int) -> np.ndarray:
    out = np.zeros((kinds, frames, size, size, 4), np.uint8)
    for k in range(kinds):
        draw = SPRITE_KINDS[k % len(SPRITE_KINDS)]
        for frame in range(frames):
            # The same generator state for every frame keeps colours fixed while poses move.
            rng = np.random.default_rng([seed, k])
            s = Sprite(size)
            draw(s, frame, frames, rng)
            out[k, frame] = d.to_rgba8(s.img, alpha=s.alpha)
    return d.frozen(out)


def furniture_sprites(size: int = 128, kinds: int = 4, frames: int = 4, seed: int = 0) -> np.ndarray:
    """(kinds, frames, size, size, 4) uint8 sRGB RGBA sprites for the furniture plane.

    Kind k is SPRITE_KINDS[k % 5]: a person waving, a floor lamp whose shade flickers,
    a person on a sofa turning a newspaper page, a potted plant swaying, a TV whose
    screen changes. Alpha is 0 where empty and 255 on the object; row 0 is the floor.
    Read-only (cached).
    """
    if size < 16 or kinds < 1 or frames < 2:
        raise ValueError(f"furniture_sprites needs size >= 16, kinds >= 1, frames >= 2; got {size}, {kinds}, {frames}")
    return _sprites(int(size), int(kinds), int(frames), int(seed))
