"""The terrain: heights on a regular grid in map metres, and the one surface every stage places
things on.

The grid is north up and axis-aligned in the map's working projection (maps/_projection.py):
sample (row, column) stands at map (west + column * spacing, north - row * spacing). Between
samples the surface is piecewise linear over two triangles per cell, split along the diagonal from
its north-east to its south-west corner: the very triangles the terrain mesh draws at its finest
level (terrain/_mesh.py), so a point placed with `height_at` lies on the drawn ground. Beyond the
grid the edge heights carry on.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely


@dataclass(frozen=True, eq=False)
class Terrain:
    """Heights in metres above the source's vertical datum. `source`: the file they came from;
    `counts`: what reading repaired, by reason ("no-data filled", "implausible value", ...)."""

    heights: np.ndarray  # (rows, columns) float32, row 0 the northern edge
    west: float  # map metres of sample (0, 0)
    north: float
    spacing: float  # metres between neighbouring samples
    source: str = ""
    counts: dict[str, int] = field(default_factory=dict)

    def __post_init__(self):
        heights = np.ascontiguousarray(self.heights, dtype=np.float32)
        if heights.ndim != 2 or min(heights.shape) < 2:
            raise ValueError(f"terrain heights must be a grid of at least 2x2 samples, got shape {heights.shape}")
        if not np.isfinite(heights).all():
            raise ValueError("terrain heights must all be finite (fill no-data before making a Terrain)")
        if not self.spacing > 0:
            raise ValueError(f"terrain spacing must be positive, got {self.spacing}")
        object.__setattr__(self, "heights", heights)

    @property
    def shape(self) -> tuple[int, int]:
        return self.heights.shape

    def bounds(self) -> tuple[float, float, float, float]:
        """(west, south, east, north) map metres of the outermost samples."""
        rows, columns = self.heights.shape
        return (
            self.west,
            self.north - (rows - 1) * self.spacing,
            self.west + (columns - 1) * self.spacing,
            self.north,
        )

    def height_at(self, x, y) -> np.ndarray:
        """Ground heights (float64, metres) at map points (east `x`, north `y`, any matching shapes)."""
        x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
        rows, columns = self.heights.shape
        column = np.clip((x - self.west) / self.spacing, 0.0, columns - 1.0)
        row = np.clip((self.north - y) / self.spacing, 0.0, rows - 1.0)
        c0 = np.minimum(np.floor(column).astype(np.int64), columns - 2)
        r0 = np.minimum(np.floor(row).astype(np.int64), rows - 2)
        u, v = column - c0, row - r0
        h = self.heights
        a, b = h[r0, c0].astype(np.float64), h[r0, c0 + 1].astype(np.float64)
        c, d = h[r0 + 1, c0].astype(np.float64), h[r0 + 1, c0 + 1].astype(np.float64)
        upper = u + v <= 1.0  # the triangle of the north-west corner
        return np.where(upper, a + u * (b - a) + v * (c - a), d + (1.0 - u) * (c - d) + (1.0 - v) * (b - d))

    def scene_height_at(self, x, z) -> np.ndarray:
        """Ground heights at scene points (x, z): the scene's z is minus north (maps.to_scene)."""
        return self.height_at(x, -np.asarray(z, np.float64))

    def lowest_on(self, geometry: shapely.Geometry) -> float:
        """The lowest ground along a map-metre geometry's outline (its rings sampled every quarter
        of a grid cell, corners included): where a building's walls meet the ground."""
        boundary = shapely.boundary(geometry) if shapely.get_dimensions(geometry) == 2 else geometry
        points = shapely.get_coordinates(shapely.segmentize(boundary, self.spacing / 4.0))
        if not len(points):
            raise ValueError("no outline to sample the terrain on")
        return float(self.height_at(points[:, 0], points[:, 1]).min())

    def relief(self) -> tuple[float, float]:
        """(lowest, highest) height of the grid."""
        return float(self.heights.min()), float(self.heights.max())
