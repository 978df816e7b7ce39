"""Where a map's scene stands on Earth, for 3D Tiles: scene points (UTM grid metres east and north
of the origin, height above the ellipsoid) to the tileset's east-north-up frame at the origin.

Grid north is not true north away from the zone's central meridian (the convergence, 1.78° at
Helsinki) and grid metres are not ground metres (the scale factor), and the ellipsoid falls away
from the origin's tangent plane; so each point is taken through pyproj to Earth-centred
coordinates (EPSG:4978) and from there into the origin's frame, instead of turning the whole scene
by one rotation."""

from __future__ import annotations

import numpy as np


class Placement:
    """Scene (x east, y up, z south) to glTF content of a tileset whose root transform is
    `transform`: x east, y up, z south of the origin's east-north-up frame (3D Tiles turns glTF's
    y-up to z-up)."""

    def __init__(self, origin: tuple[float, float], crs: str):
        import pyproj

        self.origin = (float(origin[0]), float(origin[1]))
        self._to_lonlat = pyproj.Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
        self._to_ecef = pyproj.Transformer.from_crs("EPSG:4979", "EPSG:4978", always_xy=True)
        self._grid_origin = np.array(self._to_lonlat.transform(*self.origin, direction="INVERSE"), np.float64)
        lon, lat = np.radians(self.origin)
        self._centre = np.array(self._to_ecef.transform(*self.origin, 0.0), np.float64)
        # rows: east, north, up in EPSG:4978
        self._axes = np.array(
            [
                [-np.sin(lon), np.cos(lon), 0.0],
                [-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)],
                [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)],
            ]
        )
        east = self.positions(np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]))
        step = east[1] - east[0]
        # grid east seen in the origin's frame: its angle is the convergence, its length the scale
        # the meridian convergence (radians): grid north is this far clockwise from true north, so the
        # scene turns by it counter-clockwise (about +y) into the origin's frame
        self.convergence = float(np.arctan2(step[2], step[0]))
        self.scale = float(100.0 / np.hypot(step[0], step[2]))  # the point scale factor k: grid m per m

    @property
    def transform(self) -> list[float]:
        """The root tile's transform: column-major 4x4, the east, north, up axes and the origin in EPSG:4978."""
        columns = [*self._axes[0], 0.0, *self._axes[1], 0.0, *self._axes[2], 0.0, *self._centre, 1.0]
        return [float(v) for v in columns]

    def ecef(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) scene points to EPSG:4978 metres."""
        p = np.asarray(points, np.float64).reshape(-1, 3)
        lon, lat = self._to_lonlat.transform(self._grid_origin[0] + p[:, 0], self._grid_origin[1] - p[:, 2])
        return np.column_stack(self._to_ecef.transform(lon, lat, p[:, 1]))

    def positions(self, points: np.ndarray) -> np.ndarray:
        """(n, 3) scene points to glTF content coordinates (float64)."""
        enu = (self.ecef(points) - self._centre) @ self._axes.T
        return np.column_stack([enu[:, 0], enu[:, 2], -enu[:, 1]])

    def directions(self, vectors: np.ndarray) -> np.ndarray:
        """Normals and tangents turned by the convergence (their change over a city is far below a degree)."""
        v = np.asarray(vectors, np.float64)
        c, s = np.cos(self.convergence), -np.sin(self.convergence)  # about +y by -convergence
        out = v.copy()
        out[:, 0] = c * v[:, 0] + s * v[:, 2]
        out[:, 2] = -s * v[:, 0] + c * v[:, 2]
        return out
