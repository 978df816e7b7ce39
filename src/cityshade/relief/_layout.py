"""A small facade layout generator: floors of recessed windows with sills, ledges between floors,
door niches on the ground floor and a cornice, each element with its own depth and material.

It stands in for a grammar as the source of detail maps and gives the four test facades at the
paper's sizes (fig. 12: 600x1000, 1536x2048, 1024x768, 930x1166 texels).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._maps import MATERIALS, DetailMaps

WALL, GLASS, FRAME, STONE, WOOD, BRICK = (MATERIALS.index(n) for n in MATERIALS)

# Depths in centimetres behind the cornice front (depth_unit = 1 cm).
CORNICE, LEDGE, SILL, WALL_D, FRAME_D, GLASS_D, NICHE_D, DOOR_D = 0, 6, 10, 20, 28, 34, 40, 46


@dataclass(frozen=True)
class FacadeLayout:
    """Proportions in metres; the generator fits whole floors and window bays into the facade."""

    floor_height: float = 3.2
    bay_width: float = 2.6
    window_width: float = 1.3
    window_height: float = 1.8
    sill_height: float = 0.9  # window bottom above the floor
    mullions: int = 1  # vertical bars splitting each window
    ground_floor_height: float = 4.0
    door_every: int = 3  # one door niche every N ground-floor bays
    cornice_height: float = 0.6
    ledge_height: float = 0.25
    brick_ground_floor: bool = True


# The four test facades of the paper (columns, rows, layout) at a 2 cm texel.
PAPER_FACADES = {
    "F1": (600, 1000, FacadeLayout()),
    "F2": (1536, 2048, FacadeLayout(floor_height=3.0, bay_width=2.0, window_width=1.1, mullions=2)),
    "F3": (1024, 768, FacadeLayout(floor_height=3.4, bay_width=3.4, window_width=2.2, mullions=3, door_every=2)),
    "F4": (930, 1166, FacadeLayout(bay_width=3.1, window_width=1.6, window_height=2.0, brick_ground_floor=False)),
}
PAPER_TEXEL = 0.02
DEPTH_UNIT = 0.01


class _Canvas:
    def __init__(self, cols: int, rows: int, texel: float):
        self.texel = texel
        self.depth = np.full((rows, cols), WALL_D, np.uint16)
        self.material = np.full((rows, cols), WALL, np.uint16)

    def fill(self, x0: float, y0: float, x1: float, y1: float, depth: int, material: int):
        """Paints the rectangle [x0, x1) x [y0, y1) given in metres (y up from the facade bottom)."""
        c0, c1, r0, r1 = (int(round(v / self.texel)) for v in (x0, x1, y0, y1))
        self.depth[max(r0, 0) : max(r1, 0), max(c0, 0) : max(c1, 0)] = depth
        self.material[max(r0, 0) : max(r1, 0), max(c0, 0) : max(c1, 0)] = material


def generate_facade(
    cols: int, rows: int, layout: FacadeLayout = FacadeLayout(), texel: float = PAPER_TEXEL
) -> DetailMaps:
    canvas = _Canvas(cols, rows, texel)
    width, height = cols * texel, rows * texel
    bays = max(1, int(width // layout.bay_width))
    bay = width / bays
    body_top = height - layout.cornice_height
    floors = max(1, int((body_top - layout.ground_floor_height) // layout.floor_height))
    if layout.brick_ground_floor:
        canvas.fill(0, 0, width, layout.ground_floor_height, WALL_D, BRICK)
    for b in range(bays):
        centre = (b + 0.5) * bay
        if b % layout.door_every == layout.door_every // 2:
            _door(canvas, centre, layout)
        else:
            _window(canvas, centre, 0.4 + 0.5 * (layout.ground_floor_height - layout.window_height), layout)
        for f in range(floors):
            base = layout.ground_floor_height + f * layout.floor_height
            _window(canvas, centre, base + layout.sill_height, layout)
    for f in range(floors + 1):
        y = layout.ground_floor_height + f * layout.floor_height - layout.ledge_height
        if y + layout.ledge_height < body_top:
            canvas.fill(0, y, width, y + layout.ledge_height, LEDGE, STONE)
    canvas.fill(0, body_top, width, height, CORNICE, STONE)
    canvas.fill(0, body_top - 0.15, width, body_top, LEDGE, STONE)  # cornice moulding step
    return DetailMaps(canvas.depth, canvas.material, texel, DEPTH_UNIT)


def _window(canvas: _Canvas, centre: float, bottom: float, layout: FacadeLayout):
    half, top, frame = layout.window_width / 2, bottom + layout.window_height, 0.08
    canvas.fill(centre - half, bottom, centre + half, top, FRAME_D, FRAME)
    panes = layout.mullions + 1
    pane = (layout.window_width - frame * (panes + 1)) / panes
    for p in range(panes):
        x0 = centre - half + frame + p * (pane + frame)
        canvas.fill(x0, bottom + frame, x0 + pane, top - frame, GLASS_D, GLASS)
    canvas.fill(centre - half - 0.1, bottom - 0.12, centre + half + 0.1, bottom, SILL, STONE)


def _door(canvas: _Canvas, centre: float, layout: FacadeLayout):
    half = 0.75
    canvas.fill(centre - half - 0.2, 0, centre + half + 0.2, 3.0, NICHE_D, STONE)
    canvas.fill(centre - half, 0, centre + half, 2.7, DOOR_D, WOOD)
    canvas.fill(centre - half + 0.15, 1.4, centre + half - 0.15, 2.5, DOOR_D + 4, GLASS)


def generate_bay(layout: FacadeLayout = FacadeLayout(), texel: float = 0.05) -> DetailMaps:
    """One window bay of one floor, made to repeat across a building's walls: a recessed window with
    its sill, and the ledge along the floor line at the bottom."""
    canvas = _Canvas(int(round(layout.bay_width / texel)), int(round(layout.floor_height / texel)), texel)
    _window(canvas, layout.bay_width / 2, layout.sill_height, layout)
    canvas.fill(0, 0, layout.bay_width, layout.ledge_height, LEDGE, STONE)
    return DetailMaps(canvas.depth, canvas.material, texel, DEPTH_UNIT)


def paper_facade(name: str) -> DetailMaps:
    """One of the four test facades F1..F4 at the paper's sizes."""
    cols, rows, layout = PAPER_FACADES[name]
    return generate_facade(cols, rows, layout)
