"""Roofs on top of a building's walls: the roof surfaces and the wall pieces under them (gables).

Every roof is built in the building's object space (x, z metres, y up) from the outline polygon
(with courtyard holes) and the height of the walls' top.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely


@dataclass(frozen=True)
class Roof:
    """A roof of one of `ROOF_SHAPES` rising `height` metres above the walls' top.

    `direction` (radians, object space, from +x toward +z) is where the main roof face looks,
    downhill: a gabled roof's ridge runs across it, a skillion falls toward it."""

    shape: str = "flat"
    height: float = 0.0
    direction: float = np.pi / 2  # ridge along +x, the footprint's longest side
    colour: tuple[float, float, float] | None = None  # sRGB 0..1; None: the material's colour
    material: str | None = None


FLAT_ROOF = Roof()


@dataclass
class Triangles:
    """Unindexed triangles (3 rows each) in object space: positions and unit normals; wall
    triangles also know where they stand on their outline edge (metres from its start, its length)."""

    positions: np.ndarray  # (n, 3)
    normals: np.ndarray  # (n, 3)
    along: np.ndarray | None = None  # (n,)
    edge_length: np.ndarray | None = None  # (n,)

    @staticmethod
    def empty() -> Triangles:
        return Triangles(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0))

    @staticmethod
    def join(parts: list[Triangles]) -> Triangles:
        parts = [p for p in parts if len(p.positions)]
        if not parts:
            return Triangles.empty()
        walls = all(p.along is not None for p in parts)
        return Triangles(
            np.concatenate([p.positions for p in parts]), np.concatenate([p.normals for p in parts]),
            np.concatenate([p.along for p in parts]) if walls else None,
            np.concatenate([p.edge_length for p in parts]) if walls else None,
        )


def polygon_triangles(polygon: shapely.Polygon) -> np.ndarray:
    """(n, 3, 2) triangles covering a polygon with holes, counter-clockwise in (x, z) seen from +y...

    ...meaning their normal (b - a) x (c - a) points up (+y) once lifted to 3D."""
    tris = shapely.get_coordinates(shapely.constrained_delaunay_triangles(polygon)).reshape(-1, 4, 2)[:, :3]
    if not len(tris):
        return np.zeros((0, 3, 2))
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    up = cross < 0  # x right, z toward the viewer: up-facing triangles turn clockwise in (x, z)
    tris[~up] = tris[~up][:, ::-1]
    return tris


def flat(polygon: shapely.Polygon, y: float, up: bool = True) -> Triangles:
    """The polygon as a horizontal surface at height y, facing up (a roof) or down (an underside)."""
    tris = polygon_triangles(polygon)
    if not up:
        tris = tris[:, ::-1]
    positions = np.insert(tris.reshape(-1, 2), 1, y, axis=1)
    normals = np.zeros_like(positions)
    normals[:, 1] = 1.0 if up else -1.0
    return Triangles(positions, normals)


def roof_triangles(polygon: shapely.Polygon, top: float, roof: Roof) -> tuple[Triangles, Triangles]:
    """(roof surfaces, wall pieces between the walls' top and the roof) over `polygon` at `top`."""
    return flat(polygon, top), Triangles.empty()
