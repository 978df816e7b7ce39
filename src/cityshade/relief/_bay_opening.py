"""The window bay's window as a relief opening (docs/relief.md, style 0): the glass texels of the
city's bay texture (cityshade.assets.facade_texture, alpha 0) at the pane's depth, texel for texel,
inside a ring of wall texels at depth 0 (the reveal), so the recessed glass seen head-on covers
exactly the flat bay's glass."""

from __future__ import annotations

import numpy as np

from ..assets import facade_texture
from ._grammar_source import OPENING_DEPTH
from ._layout import DEPTH_UNIT, FRAME, GLASS, WALL
from ._maps import DetailMaps


def window_bay_opening() -> DetailMaps:
    """D and M over the bounding box of the bay texture's glass, plus the ring (texel 1 map unit;
    the city stretches it over the glass rectangle of each bay). Texels of the box that are not
    glass, if any, stand at the frame's depth."""
    glass = facade_texture()[0][..., 3] < 128
    rows, cols = np.nonzero(glass)
    if not len(rows):
        raise ValueError("the window bay texture has no glass texel")
    box = glass[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1]
    depth = np.pad(np.where(box, OPENING_DEPTH["glass"], OPENING_DEPTH["frame"]), 1)
    material = np.pad(np.where(box, GLASS, FRAME), 1, constant_values=WALL)
    return DetailMaps(depth.astype(np.uint16), material.astype(np.uint16), 1.0, DEPTH_UNIT)
