"""What roof a map building has: shape, height and direction from its tags, in the mass's object space."""

from __future__ import annotations

import numpy as np
import shapely

from ..scene import Roof
from ._model import ROOF_SHAPES, MapBuilding


def building_roof(building: MapBuilding, outline: shapely.Polygon, yaw: float, height: float) -> Roof:
    """The roof of `building` over its object-space `outline`, turned by `yaw`, at most `height` tall."""
    shape = building.roof_shape if building.roof_shape in ROOF_SHAPES else "flat"
    if shape == "flat":
        return Roof(colour=building.roof_colour, material=building.roof_material)
    rise = min(building.roof_height or 0.0, height)
    return Roof(shape, rise, colour=building.roof_colour, material=building.roof_material)
