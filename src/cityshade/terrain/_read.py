"""`read_terrain`: a digital elevation model (a GeoTIFF or any raster GDAL reads, in any CRS) as the
map's Terrain.

Only the window of the raster over the map's extent and READ_MARGIN around it is read (decimated
to at most MAX_READ samples a side where the raster is finer), then reprojected with GDAL's warper
(rasterio.warp.reproject, bilinear) onto a north-up grid in the map's working projection. Heights
take the band's scale and offset and its vertical unit (the band's, else the CRS's vertical axis).
No-data samples, and values no ground has (outside PLAUSIBLE: the -9999 and 1e38 sentinels of
files that do not flag them), are holes: filled by GDAL's inverse-distance fill
(rasterio.fill.fillnodata) and, farther than FILL_SEARCH samples from any height, by the nearest
height; both are counted.
"""

from __future__ import annotations

import logging
import math
import warnings
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pyproj
import rasterio
import rasterio.errors
import rasterio.fill
import rasterio.warp
import rasterio.windows
from affine import Affine
from rasterio.enums import Resampling
from scipy import ndimage

from .._files import checked_input_size
from ..errors import UsageError
from ._grid import Terrain

READ_MARGIN = 500.0  # metres of terrain read around the map's extent
MAX_READ = 4096  # samples a side read from the file at most (finer rasters are read decimated)
# samples a side of the terrain grid at most: the grid is drawn (its finest level under the data) and
# the ground is split along it, so it bounds the triangles terrain adds (bench osm measures them)
MAX_SAMPLES = 384
MIN_SPACING = 0.5  # metres: no finer grid than this, whatever the file's resolution
PLAUSIBLE = (-1000.0, 9000.0)  # metres: heights ground can have (the Dead Sea shore to above Everest)
FILL_SEARCH = 64  # samples the inverse-distance fill reaches across a hole
FORMATS = "a GeoTIFF or another raster GDAL reads"
METRES_PER_UNIT = {
    **dict.fromkeys(("", "m", "metre", "meter", "metres", "meters"), 1.0),
    **dict.fromkeys(("ft", "foot", "feet", "international foot"), 0.3048),
    **dict.fromkeys(("us survey foot", "us survey feet", "ftus", "us-ft", "us ft"), 1200.0 / 3937.0),
    **dict.fromkeys(("cm", "centimetre", "centimeter"), 0.01),
    **dict.fromkeys(("dm", "decimetre", "decimeter"), 0.1),
    **dict.fromkeys(("mm", "millimetre", "millimeter"), 0.001),
}


class TerrainWarning(UserWarning):
    """A DEM that leaves the map flat (it does not reach the map, or holds no height there)."""


@contextmanager
def _gdal_quiet():
    """GDAL's own complaints about a bad file go to the log, not to the user: the error says it."""
    logger = logging.getLogger("rasterio")
    level = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        with rasterio.Env(CPL_DEBUG=False):
            yield
    finally:
        logger.setLevel(level)


def _reason(exc: Exception) -> str:
    return str(exc).strip().splitlines()[0].rstrip(".") if str(exc).strip() else type(exc).__name__


def _metres_per_unit(path: Path, src) -> float:
    """The vertical unit of band 1 (its own, else the CRS's vertical axis), in metres."""
    unit = (src.units[0] or "") if src.units else ""
    if not unit and src.crs is not None:
        crs = pyproj.CRS.from_wkt(src.crs.to_wkt())
        vertical = [c for c in crs.sub_crs_list if c.is_vertical] if crs.is_compound else []
        unit = vertical[0].axis_info[0].unit_name if vertical and vertical[0].axis_info else ""
    key = unit.strip().lower().replace("_", " ")
    if key not in METRES_PER_UNIT:
        raise UsageError(
            f"{path}: unknown vertical unit {unit!r} of band 1; set the band's unit to metre, foot or US survey foot"
        )
    return METRES_PER_UNIT[key]


def _map_crs(crs: str):
    if crs == "local":
        raise UsageError(
            "the map has no coordinate system (local metres), so a DEM cannot be placed on it; "
            "give the map's CRS in the file or leave out --terrain"
        )
    return rasterio.crs.CRS.from_user_input(crs)


def _source_crs(path: Path, src):
    if src.crs is None:
        raise UsageError(
            f"{path}: the DEM has no coordinate system; georeference it (e.g. gdal_edit.py -a_srs EPSG:...)"
        )
    try:
        crs = pyproj.CRS.from_wkt(src.crs.to_wkt())
    except pyproj.exceptions.CRSError as exc:
        raise UsageError(f"{path}: unknown coordinate system ({_reason(exc)}); give the DEM a known CRS") from None
    plan = crs.sub_crs_list[0] if crs.is_compound else crs
    if not (plan.is_geographic or plan.is_projected):  # a site grid or engineering CRS: not tied to the Earth
        raise UsageError(
            f"{path}: the DEM's coordinate system {crs.name!r} is not tied to the Earth; "
            "give the DEM a geographic or projected CRS (e.g. gdal_edit.py -a_srs EPSG:...)"
        )
    return src.crs


def _window(path: Path, src, src_crs, dst_crs, region) -> rasterio.windows.Window | None:
    """The raster's window over `region` (left, bottom, right, top in the map's projection), whole
    samples with one more around for the interpolation; None where the raster does not reach it."""
    try:
        left, bottom, right, top = rasterio.warp.transform_bounds(dst_crs, src_crs, *region, densify_pts=21)
    except (rasterio.errors.CRSError, pyproj.exceptions.ProjError, ValueError) as exc:
        raise UsageError(f"{path}: cannot relate the DEM's coordinate system to the map's ({_reason(exc)})") from None
    if not all(math.isfinite(v) for v in (left, bottom, right, top)):
        return None
    wanted = rasterio.windows.from_bounds(left, bottom, right, top, transform=src.transform)
    first_row, first_col = math.floor(wanted.row_off) - 1, math.floor(wanted.col_off) - 1
    last_row = math.ceil(wanted.row_off + wanted.height) + 1
    last_col = math.ceil(wanted.col_off + wanted.width) + 1
    row0, col0 = max(first_row, 0), max(first_col, 0)
    row1, col1 = min(last_row, src.height), min(last_col, src.width)
    if row1 <= row0 or col1 <= col0:
        return None
    return rasterio.windows.Window(col0, row0, col1 - col0, row1 - row0)


def _read_window(path: Path, src, window) -> tuple[np.ndarray, Affine, int]:
    """(heights in metres with holes as NaN, their transform, implausible values dropped)."""
    scale = max(window.width, window.height) / MAX_READ
    shape = (window.height, window.width)
    if scale > 1:
        shape = (max(2, round(window.height / scale)), max(2, round(window.width / scale)))
    try:
        band = src.read(1, window=window, out_shape=shape, masked=True, resampling=Resampling.nearest)
    except (rasterio.errors.RasterioError, MemoryError) as exc:
        raise UsageError(f"{path}: cannot read the DEM's heights ({_reason(exc)}); the file may be truncated") from None
    raw = np.ma.getdata(band).astype(np.float64)
    holes = np.ma.getmaskarray(band) | ~np.isfinite(raw)
    offset = src.offsets[0] if src.offsets and src.offsets[0] is not None else 0.0
    factor = src.scales[0] if src.scales and src.scales[0] is not None else 1.0
    heights = (raw * factor + offset) * _metres_per_unit(path, src)
    implausible = ~holes & ((heights < PLAUSIBLE[0]) | (heights > PLAUSIBLE[1]))
    heights[holes | implausible] = np.nan
    transform = src.window_transform(window) @ Affine.scale(window.width / shape[1], window.height / shape[0])
    return heights.astype(np.float32), transform, int(implausible.sum())


def _spacing(src_crs, dst_crs, transform: Affine, shape, region) -> float:
    """The grid spacing: about the source's resolution in map metres, within MIN_SPACING and a grid
    of MAX_SAMPLES a side over `region`."""
    rows, columns = shape
    west, north = transform @ (0, 0)
    east, south = transform @ (columns, rows)
    native, _, _ = rasterio.warp.calculate_default_transform(
        src_crs, dst_crs, columns, rows, min(west, east), min(south, north), max(west, east), max(south, north)
    )
    extent = max(region[2] - region[0], region[3] - region[1])
    return max(abs(native.a), MIN_SPACING, extent / (MAX_SAMPLES - 1))


def _fill(heights: np.ndarray) -> int:
    """Fills the NaN holes of `heights` in place; returns how many there were."""
    holes = ~np.isfinite(heights)
    count = int(holes.sum())
    if count:
        heights[:] = rasterio.fill.fillnodata(
            np.where(holes, 0.0, heights).astype(np.float32),
            mask=(~holes).astype(np.uint8),
            max_search_distance=FILL_SEARCH,
        )
        filled = np.isfinite(heights) & (~holes | (heights != 0.0))  # fillnodata leaves far holes as they were (0)
        far = holes & ~filled
        if far.any():
            nearest = ndimage.distance_transform_edt(far, return_distances=False, return_indices=True)
            heights[far] = heights[tuple(index[far] for index in nearest)]
    return count


def read_terrain(
    path: Path | str, crs: str, origin: tuple[float, float], bounds: tuple[float, float, float, float]
) -> Terrain | None:
    """The terrain of a DEM file under a map: `crs` and `origin` (longitude, latitude of map point
    (0, 0)) its working projection, `bounds` its extent (west, south, east, north map metres).
    None, with a TerrainWarning, when the DEM does not reach the map or holds no height there."""
    path = Path(path)
    checked_input_size(path, "DEM", FORMATS)
    dst_crs = _map_crs(crs)
    ox, oy = pyproj.Transformer.from_crs("EPSG:4326", pyproj.CRS.from_user_input(crs), always_xy=True).transform(
        *origin
    )
    x0, y0, x1, y1 = bounds[0] - READ_MARGIN, bounds[1] - READ_MARGIN, bounds[2] + READ_MARGIN, bounds[3] + READ_MARGIN
    region = (x0 + ox, y0 + oy, x1 + ox, y1 + oy)  # in the projection, before the shift to the map's origin
    with _gdal_quiet():
        try:
            src = rasterio.open(path)
        except rasterio.errors.RasterioError as exc:
            raise UsageError(f"{path}: not a raster GDAL can read ({_reason(exc)}); give {FORMATS}") from None
        with src:
            src_crs = _source_crs(path, src)
            window = _window(path, src, src_crs, dst_crs, region)
            if window is None:
                warnings.warn(f"{path}: the DEM does not reach the map; the ground stays flat", TerrainWarning, 2)
                return None
            source, transform, implausible = _read_window(path, src, window)
    if not np.isfinite(source).any():
        warnings.warn(f"{path}: the DEM holds no height under the map; the ground stays flat", TerrainWarning, 2)
        return None
    spacing = _spacing(src_crs, dst_crs, transform, source.shape, region)
    columns = int(np.ceil((x1 - x0) / spacing)) + 1
    rows = int(np.ceil((y1 - y0) / spacing)) + 1
    grid = np.full((rows, columns), np.nan, np.float32)
    # pixel-is-area: sample (r, c) is the centre of a cell whose corner is half a spacing west and north
    dst_transform = Affine(spacing, 0.0, region[0] - spacing / 2, 0.0, -spacing, region[3] + spacing / 2)
    with _gdal_quiet():
        rasterio.warp.reproject(
            source,
            grid,
            src_transform=transform,
            src_crs=src_crs,
            src_nodata=np.nan,
            dst_transform=dst_transform,
            dst_crs=dst_crs,
            dst_nodata=np.nan,
            resampling=Resampling.bilinear,
        )
    if not np.isfinite(grid).any():
        warnings.warn(f"{path}: the DEM holds no height under the map; the ground stays flat", TerrainWarning, 2)
        return None
    counts = {"no-data filled": _fill(grid), "implausible values": implausible}
    return Terrain(grid, x0, y1, spacing, str(path), {k: v for k, v in counts.items() if v})
