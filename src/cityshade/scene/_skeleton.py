"""Straight skeletons of building outlines through CGAL (the pySVCGAL wrapper): the faces of a
hipped roof over any outline, courtyards included."""

from __future__ import annotations

import contextlib
import io
import os
from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np
import shapely

with contextlib.redirect_stdout(io.StringIO()):  # the wrapper prints a line when imported
    from pySVCGAL.pySVCGAL import pySVCGAL_straight_skeleton_2d_extrude as _extrude

HIP = 45.0  # degrees: a face's height is its distance from its outline edge
AHEAD_WORKERS = 2  # threads computing skeletons ahead: more than the spare cores only compete


def _rings(polygon: shapely.Polygon) -> list[np.ndarray]:
    """The outline's rings without their closing point: exterior counter-clockwise, holes clockwise."""
    polygon = shapely.orient_polygons(polygon)
    return [np.asarray(r.coords)[:-1] for r in (polygon.exterior, *polygon.interiors)]


def skeleton_triangles(polygon: shapely.Polygon) -> np.ndarray | None:
    """The skeleton's roof as (n, 3, 3) triangles of (x, z, height above the outline = distance from
    the face's outline edge); None if CGAL fails. Taken from skeletons_ahead where it has them."""
    if polygon.wkb in _AHEAD:
        return _AHEAD[polygon.wkb].result()
    with contextlib.redirect_stdout(io.StringIO()):
        return _skeleton(polygon)


def _skeleton(polygon: shapely.Polygon) -> np.ndarray | None:
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


_AHEAD: dict[bytes, Future] = {}  # outline (WKB) -> its skeleton, being computed


@contextlib.contextmanager
def skeletons_ahead(polygons: list[shapely.Polygon]):
    """Within the block, the skeletons of `polygons` are computed on threads while the caller goes
    on (the CGAL binding lets go of the GIL), and skeleton_triangles waits for them instead of
    computing them again. Standard output is quiet within the block (the binding prints errors)."""
    workers = min(os.cpu_count() or 1, AHEAD_WORKERS)
    with contextlib.redirect_stdout(io.StringIO()), ThreadPoolExecutor(workers) as pool:
        mine = {}
        for polygon in polygons:
            if polygon.wkb not in _AHEAD and polygon.wkb not in mine:
                mine[polygon.wkb] = pool.submit(_skeleton, polygon)
        _AHEAD.update(mine)
        try:
            yield
        finally:
            for key in mine:
                _AHEAD.pop(key).cancel()


def ring_edges(polygon: shapely.Polygon) -> list[tuple[np.ndarray, np.ndarray]]:
    """(start, end) of every outline edge in the numbering `skeleton_faces` uses."""
    return [(ring[i], ring[(i + 1) % len(ring)]) for ring in _rings(polygon) for i in range(len(ring))]
