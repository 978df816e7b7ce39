"""Synthetic DEMs for tests and benchmarks: a height function of map metres written as a GeoTIFF in
any CRS over a map's extent (rasterio), so each reading path is tried on a file with known heights."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyproj
import rasterio
import rasterio.warp
from rasterio.transform import from_origin


def write_dem(path: Path, heights: np.ndarray, crs, west: float, north: float, spacing: float, **profile) -> Path:
    """`heights` (rows, columns; row 0 north) as a one-band GeoTIFF with square pixels of `spacing`
    CRS units whose north-west corner is (`west`, `north`); `profile`: more creation options."""
    heights = np.asarray(heights)
    options = {"driver": "GTiff", "count": 1, "dtype": heights.dtype.name, "crs": crs, **profile}
    transform = from_origin(west, north, spacing, spacing)
    with rasterio.open(
        path, "w", height=heights.shape[0], width=heights.shape[1], transform=transform, **options
    ) as dst:
        dst.write(heights, 1)
    return path


def dem_over(
    path: Path,
    map_crs: str,
    origin: tuple[float, float],
    bounds: tuple[float, float, float, float],
    surface: Callable[[np.ndarray, np.ndarray], np.ndarray],
    dem_crs=None,
    samples: int = 200,
    margin: float = 600.0,
    dtype=np.float32,
    **profile,
) -> Path:
    """A DEM of `surface(x, y)` (heights at map metres) over `bounds` (map metres, west, south, east,
    north) and `margin` around, `samples` pixels a side, in `dem_crs` (default the map's own)."""
    dem_crs = rasterio.crs.CRS.from_user_input(dem_crs or map_crs)
    to_map = pyproj.Transformer.from_crs(pyproj.CRS.from_wkt(dem_crs.to_wkt()), map_crs, always_xy=True)
    ox, oy = pyproj.Transformer.from_crs("EPSG:4326", map_crs, always_xy=True).transform(*origin)
    west, south, east, north = bounds
    region = (west - margin + ox, south - margin + oy, east + margin + ox, north + margin + oy)
    left, bottom, right, top = rasterio.warp.transform_bounds(map_crs, dem_crs, *region, densify_pts=21)
    spacing = max(right - left, top - bottom) / samples
    columns, rows = np.meshgrid(np.arange(samples) + 0.5, np.arange(samples) + 0.5)
    x, y = to_map.transform(left + columns * spacing, top - rows * spacing)
    heights = np.asarray(surface(np.asarray(x) - ox, np.asarray(y) - oy), dtype=dtype)
    return write_dem(path, heights, dem_crs, left, top, spacing, **profile)
