"""The polygonised-interiors baseline (interior-mapping §3.1, fig. 9): real geometry behind the
windows instead of a per-pixel ray cast.

Every box building gets one floor quad per storey (facing up), one ceiling quad per storey
(facing down) and, on every wall line of its regular room grid, a full-height quad facing each
room beside it (the facades' inner sides included), so each room is closed by real walls. The
quads are single-sided: drawn with back-face culling, a floor and the ceiling below it share a
plane without fighting. Vertices use the buildings' batched format (scene VERTEX_DTYPE) with the
face code (FACE_FLOOR, FACE_CEILING, FACE_WALL_X, FACE_WALL_Z) as the surface kind, so the same
chunked culling and building records serve both methods. Room walls are not displaced (§4.3):
the baseline is the paper's regular apartment block.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..scene import VERTEX_DTYPE, BuildingMass, world_positions
from ._faces import FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z

LAYERS = ("floors", "ceilings", "walls")  # one texture kind, one vertex buffer, one draw call each


def room_grid(mass: BuildingMass) -> tuple[int, int, int]:
    """Rooms along x, storeys, rooms along z: the grid interior mapping casts into."""
    counts = np.rint(mass.extent / mass.room_size).astype(int)
    return int(counts[0]), int(counts[1]), int(counts[2])


def quad_counts(mass: BuildingMass) -> dict[str, int]:
    """Quads per layer for one building: storeys, storeys, 2 per room column and row."""
    nx, ny, nz = room_grid(mass)
    return {"floors": ny, "ceilings": ny, "walls": 2 * (nx + nz)}


def _quads(mass: BuildingMass) -> dict[str, list[tuple[np.ndarray, np.ndarray, int]]]:
    """(4 corners counter-clockwise seen from the room, room-facing normal, face code) per layer."""
    width, height, depth = mass.extent
    sx, sy, sz = mass.room_size
    nx, ny, nz = room_grid(mass)
    layers: dict[str, list] = {name: [] for name in LAYERS}
    for k in range(ny):
        for y, up, name, face in ((k * sy, 1.0, "floors", FACE_FLOOR), ((k + 1) * sy, -1.0, "ceilings", FACE_CEILING)):
            corners = np.array([(0, y, 0), (width, y, 0), (width, y, depth), (0, y, depth)], float)
            layers[name].append((corners, np.array([0.0, up, 0.0]), face))
    for axis, count, size, span, face in ((0, nx, sx, depth, FACE_WALL_X), (2, nz, sz, width, FACE_WALL_Z)):
        other = 2 - axis
        for k in range(count + 1):
            for facing in (1.0, -1.0):  # the room on the + side, then the room on the - side
                if (facing > 0 and k == count) or (facing < 0 and k == 0):
                    continue  # outside the building
                corners = np.zeros((4, 3))
                corners[:, axis] = k * size
                corners[:, other] = (0, span, span, 0)
                corners[:, 1] = (0, 0, height, height)
                normal = np.zeros(3)
                normal[axis] = facing
                layers["walls"].append((corners, normal, face))
    return layers


def _triangles(corners: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Two triangles wound counter-clockwise seen from the side the normal points to."""
    a, b, c, _ = corners
    order = (0, 1, 2, 0, 2, 3) if np.dot(np.cross(b - a, c - a), normal) > 0 else (0, 2, 1, 0, 3, 2)
    return corners[list(order)]


def polygonised_vertices(masses: Sequence[BuildingMass]) -> dict[str, np.ndarray]:
    """The whole city's interior geometry, one VERTEX_DTYPE triangle list per layer (LAYERS)."""
    rows: dict[str, list[np.ndarray]] = {name: [] for name in LAYERS}
    for index, mass in enumerate(masses):
        if mass.shape != "prism" or len(mass.footprint) != 4:
            raise ValueError(
                f"polygonised interiors need box buildings; building {index} is a {mass.shape} "
                f"with {len(mass.footprint)} footprint corners"
            )
        origin = np.asarray(mass.position, np.float64)
        for name, quads in _quads(mass).items():
            if not quads:
                continue
            out = np.zeros(6 * len(quads), dtype=VERTEX_DTYPE)
            out["local"] = np.concatenate([_triangles(c, n) for c, n, _ in quads])
            out["normal"] = np.repeat([n for _, n, _ in quads], 6, axis=0)
            out["ids"][:, 0] = index
            out["ids"][:, 1] = np.repeat([face for _, _, face in quads], 6)
            out["position"] = world_positions(out["local"], np.cos(mass.yaw), np.sin(mass.yaw), origin)
            rows[name].append(out)
    return {name: np.concatenate(parts) if parts else np.zeros(0, VERTEX_DTYPE) for name, parts in rows.items()}
