"""Reading a DEM under a map: windowed, reprojected, holes filled and counted, bad files refused in one
line (terrain.read_terrain, maps.load_map(terrain=...), --terrain)."""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_origin

from cityshade.errors import UsageError
from cityshade.maps import load_map
from cityshade.terrain import TerrainWarning, read_terrain
from cityshade.terrain.testing import dem_over, write_dem

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


@pytest.fixture(scope="module")
def flat_map():
    return load_map(TAGGED)


def slope(x, y):
    return 50.0 + 0.1 * x - 0.05 * y


def _read(path, data):
    return read_terrain(path, data.crs, data.origin, data.bounds())


def _inside(data, n=400, seed=0):
    west, south, east, north = data.bounds()
    rng = np.random.default_rng(seed)
    return rng.uniform(west, east, n), rng.uniform(south, north, n)


@pytest.mark.parametrize("dem_crs, tolerance", [(None, 0.02), ("EPSG:3067", 0.05), ("EPSG:4326", 0.05)])
def test_a_slope_reads_back_in_any_crs(tmp_path, flat_map, dem_crs, tolerance):
    path = dem_over(tmp_path / "slope.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), slope, dem_crs)
    terrain = _read(path, flat_map)
    x, y = _inside(flat_map)
    error = np.abs(terrain.height_at(x, y) - slope(x, y))
    assert error.max() < tolerance, f"{dem_crs}: worst error {error.max():.3f} m over {len(x)} points"
    assert terrain.counts == {}


def test_a_valley_and_a_cliff_keep_their_shape(tmp_path, flat_map):
    def valley(x, y):
        return 0.004 * x**2 + 10.0

    def cliff(x, y):
        return np.where(x > 0.0, 30.0, 0.0)

    x, y = _inside(flat_map)
    bottom = _read(
        dem_over(tmp_path / "valley.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), valley), flat_map
    )
    assert np.abs(bottom.height_at(x, y) - valley(x, y)).max() < 0.5  # curvature between samples of ~7 m
    drop = _read(dem_over(tmp_path / "cliff.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), cliff), flat_map)
    far = np.abs(x) > 2 * drop.spacing  # the cliff's own cells are a steep ramp between its samples
    assert np.abs(drop.height_at(x, y) - cliff(x, y))[far].max() < 1e-3
    assert drop.relief() == (0.0, 30.0)


def test_holes_and_unflagged_sentinels_are_filled_and_counted(tmp_path, flat_map):
    def holed(x, y):
        h = slope(x, y)
        h[(np.abs(x) < 30) & (np.abs(y) < 30)] = -9999.0  # flagged no-data
        h[(np.abs(x - 100) < 20) & (np.abs(y) < 20)] = -10000.0  # absurd, not flagged
        h[(np.abs(x + 100) < 20) & (np.abs(y) < 20)] = 1e38  # a sentinel left unflagged
        return h

    path = dem_over(tmp_path / "holes.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), holed, nodata=-9999.0)
    terrain = _read(path, flat_map)
    assert terrain.counts["no-data filled"] > 0
    assert terrain.counts["implausible values"] > 0
    for cx in (0.0, 100.0, -100.0):  # the fill bridges each hole from its sides: a slope stays a slope
        assert abs(float(terrain.height_at(cx, 0.0)) - slope(cx, 0.0)) < 1.0
    assert np.isfinite(terrain.heights).all() and terrain.relief()[1] < 200


def test_a_dem_over_part_of_the_map_carries_its_edge_on_and_counts(tmp_path, flat_map):
    west, south, east, north = flat_map.bounds()
    path = dem_over(tmp_path / "half.tif", flat_map.crs, flat_map.origin, (west, south, 0.0, north), slope, margin=20)
    terrain = _read(path, flat_map)
    assert terrain.counts["no-data filled"] > 0
    assert abs(float(terrain.height_at(west + 5, 0.0)) - slope(west + 5, 0.0)) < 0.05
    assert np.isfinite(terrain.height_at(east, north))


def test_the_map_reads_its_terrain_and_reports_the_repairs(tmp_path, flat_map):
    path = dem_over(tmp_path / "slope.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), slope, nodata=-1.0)
    with rasterio.open(path, "r+") as dst:
        block = dst.read(1)
        block[90:100, 90:100] = -1.0
        dst.write(block, 1)
    data = load_map(TAGGED, terrain=path)
    assert data.terrain is not None and data.report.repaired[("terrain samples", "no-data filled")] > 0


def test_vertical_units_and_scale_come_from_the_file(tmp_path, flat_map):
    path = dem_over(
        tmp_path / "feet.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), lambda x, y: slope(x, y) / 0.3048 * 10
    )
    with rasterio.open(path, "r+") as dst:
        dst.units = ("ft",)
        dst.scales = (0.1,)
    x, y = _inside(flat_map)
    assert np.abs(_read(path, flat_map).height_at(x, y) - slope(x, y)).max() < 0.02


def test_a_dem_elsewhere_warns_and_leaves_the_map_flat(tmp_path, flat_map):
    path = write_dem(tmp_path / "far.tif", np.ones((10, 10), np.float32), "EPSG:32635", 100000.0, 100000.0, 10.0)
    with pytest.warns(TerrainWarning, match="does not reach the map"):
        assert load_map(TAGGED, terrain=path).terrain is None


def test_a_huge_raster_is_read_windowed(tmp_path, flat_map):
    """A 50,000 x 50,000 sparse tiled GeoTIFF (10 GB as float32 if read whole, a few KB on disk) with
    the map in one corner: only its window is read."""
    ox, oy = 385700.0, 6672100.0  # about the map's UTM 35N position, rounded
    west, north = ox - 2000.0, oy + 48000.0
    path = tmp_path / "huge.tif"
    profile = {"tiled": True, "blockxsize": 512, "blockysize": 512, "sparse_ok": True, "nodata": -9999.0}
    profile["compress"] = "deflate"
    with rasterio.open(
        path, "w", driver="GTiff", height=50000, width=50000, count=1, dtype="float32", crs="EPSG:32635",
        transform=from_origin(west, north, 1.0, 1.0), **profile,
    ) as dst:  # fmt: skip
        window = rasterio.windows.Window(0, 46000, 4000, 4000)  # the map and its margin
        dst.write(np.full((4000, 4000), 12.5, np.float32), 1, window=window)
    assert path.stat().st_size < 2**20
    start = time.perf_counter()
    terrain = _read(path, flat_map)
    assert time.perf_counter() - start < 20.0  # a whole read would take minutes and 10 GB
    assert terrain is not None and np.allclose(terrain.heights, 12.5)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda p: p.mkdir(), "is a directory"),
        (lambda p: p.write_bytes(b""), "the file is empty"),
        (lambda p: p.write_bytes(b"II*\x00" + bytes(range(256)) * 40), "not a raster GDAL can read"),
    ],
)
def test_bad_files_are_one_line_errors(tmp_path, flat_map, make, message):
    path = tmp_path / "bad.tif"
    make(path)
    with pytest.raises(UsageError, match=message) as caught:
        _read(path, flat_map)
    assert "\n" not in str(caught.value) and str(path) in str(caught.value)


def test_a_truncated_tiff_is_a_one_line_error(tmp_path, flat_map):
    path = dem_over(tmp_path / "whole.tif", flat_map.crs, flat_map.origin, flat_map.bounds(), slope, samples=600)
    data = path.read_bytes()
    cut = tmp_path / "cut.tif"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(UsageError, match="truncated|cannot read|not a raster") as caught:
        _read(cut, flat_map)
    assert "\n" not in str(caught.value)


def test_a_dem_without_a_known_crs_is_refused(tmp_path, flat_map):
    none = write_dem(tmp_path / "nocrs.tif", np.ones((10, 10), np.float32), None, 0.0, 10.0, 1.0)
    with pytest.raises(UsageError, match="no coordinate system"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # rasterio's NotGeoreferencedWarning
        _read(none, flat_map)
    engineering = 'LOCAL_CS["site grid",LOCAL_DATUM["site",0],UNIT["metre",1],AXIS["x",EAST],AXIS["y",NORTH]]'
    local = write_dem(tmp_path / "local.tif", np.ones((10, 10), np.float32), engineering, 0.0, 10.0, 1.0)
    with pytest.raises(UsageError, match="coordinate system") as caught:
        _read(local, flat_map)
    assert "\n" not in str(caught.value)
