"""Estimates of levels, storey height and roof shape for every building of a map.

First version: the regional defaults per building type (`_defaults.py`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._defaults import SMALL_FOOTPRINT, defaults_for
from ._model import MapBuilding


@dataclass
class Estimates:
    levels: np.ndarray  # storeys below the roof
    storey: np.ndarray  # metres floor to floor
    roof_shape: np.ndarray  # object array of ROOF_SHAPES values


def estimate(buildings: list[MapBuilding], shape) -> Estimates:
    defaults = [defaults_for(b.kind) for b in buildings]
    small = shape.area < SMALL_FOOTPRINT
    levels = np.array([d.levels for d in defaults], float)
    levels[small] = 1.0
    storey = np.array([d.storey for d in defaults], float)
    roof = np.array([d.roof_shape for d in defaults], dtype=object)
    return Estimates(levels, storey, roof)
