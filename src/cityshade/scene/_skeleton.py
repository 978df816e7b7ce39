"""Straight skeletons of building outlines through CGAL (the pySVCGAL wrapper): the faces of a
hipped roof over any outline, courtyards included."""

from __future__ import annotations

import contextlib
import io

import numpy as np
import shapely

with contextlib.redirect_stdout(io.StringIO()):  # the wrapper prints a line when imported
    from pySVCGAL.pySVCGAL import pySVCGAL_straight_skeleton_2d_extrude as _extrude

HIP = 45.0  # degrees: a face's height is its distance from its outline edge


def _rings(polygon: shapely.Polygon) -> list[np.ndarray]:
    """The outline's rings without their closing point: exterior counter-clockwise, holes clockwise."""
    polygon = shapely.orient_polygons(polygon)
    return [np.asarray(r.coords)[:-1] for r in (polygon.exterior, *polygon.interiors)]


def skeleton_triangles(polygon: shapely.Polygon) -> np.ndarray | None:
    """The skeleton's roof as (n, 3, 3) triangles of (x, z, height above the outline = distance from
    the face's outline edge); None if CGAL fails."""
    rings = _rings(polygon)
    angles = [[HIP] * len(ring) for ring in rings]
    contours = [[(float(x), float(z), 0.0) for x, z in ring] for ring in rings]
    data = {
        "objects": [
            {"shape_mode": 0, "restrict_height": False, "height": 0.0, "planes": [contours], "angles": [angles]}
        ],
        "only_tests_for_valid": False,
        "force_z_zero": False,
        "join_mode": 0,
        "verbose": False,
    }
    with contextlib.redirect_stdout(io.StringIO()):
        result = _extrude(data)
    if not result["objects"] or any(e["descriptions_per_errors"] for e in result["source_objects_errors"]):
        return None
    mesh = result["objects"][0]
    vertices = np.asarray(mesh["vertices"], dtype=np.float64)
    faces = [face for face in mesh["faces"] if len(face) == 3]
    if len(faces) < len(mesh["faces"]):
        return None
    tris = vertices[np.asarray(faces, dtype=np.int64).reshape(-1, 3)]
    return tris[tris[:, :, 2].max(axis=1) > 1e-6]  # the flat cap at the outline's level is not a roof


def ring_edges(polygon: shapely.Polygon) -> list[tuple[np.ndarray, np.ndarray]]:
    """(start, end) of every outline edge in the numbering `skeleton_faces` uses."""
    return [(ring[i], ring[(i + 1) % len(ring)]) for ring in _rings(polygon) for i in range(len(ring))]
