"""A roof with what stands on it: rooftop units on the flat roofs inside parapets, dormers on
gabled and hipped roofs with rooms in them."""

from __future__ import annotations

import numpy as np
import shapely

from ._dormers import dormers
from ._roof_units import rooftop_units
from ._roofs import Roof, Triangles, parapet_roofs, roof_triangles


def roof_with_rooftop(polygon: shapely.Polygon, top: float, roof: Roof) -> tuple[Triangles, Triangles, Triangles]:
    """roof_triangles (roof surfaces, wall pieces) with the rooftop units or dormers added to the
    roof, and the dormers' fronts (wall pieces numbered dormer by dormer: Triangles.piece)."""
    if (roof.shape == "flat" or roof.height <= 0) and roof.parapet > 0:
        inside = parapet_roofs(np.array([polygon]), np.array([top]), np.array([roof.parapet]))
        units = [rooftop_units(piece, top - roof.parapet, roof.seed) for piece in inside.pieces]
        return Triangles.join([inside.rows, *units]), Triangles.empty(), Triangles.empty()
    surface, walls = roof_triangles(polygon, top, roof)
    if roof.shape == "flat" or roof.height <= 0:
        return surface, walls, Triangles.empty()
    cover, fronts = dormers(polygon, top, roof, surface)
    return Triangles.join([surface, cover]), walls, fronts
