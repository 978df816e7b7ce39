"""The flat ground of a map as triangles with a material each, split so that no two surfaces
overlap (nothing to z-fight).

The map features claim surfaces with a rank (features/_feature.py); they are decided in rank order
(a road crossing a park is road, a park by a river keeps its bank): each surface is its geometry
minus every one ranked above it (vectorised shapely), and every polygon is triangulated with its
holes by earcut (mapbox_earcut).
"""

from __future__ import annotations

import mapbox_earcut as earcut
import numpy as np
import shapely

from ._model import to_scene

PAINT_LIFT = 0.03  # markings and rails over the carriageway


def _earcut(polygon: shapely.Polygon) -> np.ndarray:
    """(K*3, 2) corners of the triangles of one polygon with its holes (mapbox earcut)."""
    rings = [shapely.get_coordinates(ring)[:-1] for ring in (polygon.exterior, *polygon.interiors)]
    corners = np.concatenate(rings)
    ends = np.cumsum([len(ring) for ring in rings]).astype(np.uint32)
    return corners[earcut.triangulate_float64(corners, ends)]


def triangles(geometry, y: float, material: int) -> np.ndarray:
    """(N*3, 4) float32 vertices (x, y, z, material) of a map-space polygonal geometry, triangulated."""
    parts = shapely.get_parts(shapely.get_parts(geometry))
    parts = parts[(shapely.get_type_id(parts) == 3) & ~shapely.is_empty(parts)] if len(parts) else parts
    if not len(parts):
        return np.zeros((0, 4), np.float32)
    scene = to_scene(np.concatenate([_earcut(p) for p in parts]))
    out = np.empty((len(scene), 4), np.float32)
    out[:, 0], out[:, 1], out[:, 2], out[:, 3] = scene[:, 0], y, scene[:, 1], material
    return out


def union_of(geometries) -> shapely.Geometry:
    """The union of the geometries that are not None or empty (an empty polygon if none is)."""
    geometries = [g for g in np.asarray(geometries, dtype=object).ravel() if g is not None and not g.is_empty]
    return shapely.union_all(geometries) if geometries else shapely.Polygon()


def cut_surfaces(surfaces) -> list[np.ndarray]:
    """The triangles of each surface (features/_feature.Surface) where none ranked above it lies,
    in the order given; the surfaces are decided by rank (the first of equal ranks first)."""
    cut = [np.zeros((0, 4), np.float32) for _ in surfaces]
    taken = shapely.Polygon()
    for i in sorted(range(len(surfaces)), key=lambda i: surfaces[i].rank):
        geometry = surfaces[i].geometry
        if geometry.is_empty:
            continue
        own = shapely.difference(geometry, taken) if not taken.is_empty else geometry
        cut[i] = triangles(own, 0.0, surfaces[i].material)
        taken = shapely.union(taken, geometry)
    return cut
