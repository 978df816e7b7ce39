"""`cityshade bench scale`: how frame time, memory and load time grow with the city.

Cities of 1,000, 10,000 and 100,000 buildings from the built-in generator (`default_city(blocks=N)`)
and from OpenStreetMap (the Helsinki extract's buildings tiled, `maps.tiled_extract`), each measured
in a Python process of its own: load time (city built, meshed, uploaded), resident memory the city
added, GPU buffer bytes, and frame times at 1024x768 without MSAA along a street walk and an aerial
pan. In every process with more than 1,000 buildings, the 1,000-building city of the same source is
drawn too, its frames taking turns with the big city's, so the growth ratios compare frames drawn
under the same load. The largest generator city is also walked in the viewer's draw path (headless,
with the target frame rate on) for `viewer_fps_llvmpipe`. The 1,000-building generator city's street
walk is also drawn with the grammar cache and without, frame by frame in turn, for
`grammar_cache_speedup`, and its street view profiled pass by pass (`Renderer.draw(profile=True)`,
as `cityshade render --profile` times them).
"""

from __future__ import annotations

import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import moderngl
import numpy as np

from .._budget import release_freed_memory
from ..errors import CityshadeError
from ..render import Renderer, RenderSettings
from ..scene import PATHS, Camera, City, default_city
from ..trees import PAPER_RATES
from ._harness import BenchResult, method_record, time_interleaved, timing_record

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
COUNTS = (1_000, 10_000, 100_000)
BLOCKS = {1_000: 10, 10_000: 32, 100_000: 102}  # default_city(blocks=N): 948, 9,865 and 100,349 buildings
SIZE = (1024, 768)
FULL_FRAMES, QUICK_FRAMES = 60, 3  # per camera path (a 100,000-building frame takes a minute here)
PROFILE_FRAMES = 3  # the biggest city's street view drawn with each pass timed: the median per pass
VIEWER_FRAMES = {False: 60, True: 24}  # quick: enough for the smallest scale and every quality step (3 frames each)
TARGET_FPS = 15.0
CULLING_VIEWS = ("street", "aerial")  # the 1,000-building cities drawn with GPU culling and without
SETTLE_FRAMES = max(rate.every for rate in PAPER_RATES)  # cascades are redrawn at their own rates: all within this
AERIAL_PAN = 0.05  # the aerial path moves the viewpoint sideways by this share of the city's width
# the numbers on this machine kind (1024x768, no MSAA), and the paper's
TODAY = [
    ("built-in generator, today (issue)", 329, 1.46, 0.85),
    ("built-in generator, today (issue)", 22_208, 5.7, 7.0),
]
PAPER = ("grammar buildings, GTX 470 (paper)", 20_000, "18-130 fps (0.008-0.056 s)")


class ScaleResult(BenchResult):
    """The harness's result with the ratios this branch cannot measure yet and why (`missing`)."""

    def __init__(self, device: str, missing: dict[str, str]):
        super().__init__("scale", device)
        self.missing = missing

    def to_json(self) -> dict:
        return {**super().to_json(), "missing": self.missing}


# -- one city, in a process of its own ----------------------------------------------------------------


def _resident_bytes() -> int:
    """The process's resident memory now (Linux /proc), else its peak."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _buffer_bytes(*owners) -> int:
    """Bytes of the GL buffers these objects (and the objects they hold) allocated."""
    seen, total, stack = set(), 0, list(owners)
    while stack:
        owner = stack.pop()
        if id(owner) in seen or owner is None:
            continue
        seen.add(id(owner))
        if isinstance(owner, moderngl.Buffer):
            total += owner.size
        elif isinstance(owner, dict):  # e.g. the trees' instance buffers, by species and level
            stack.extend(owner.values())
        elif isinstance(owner, (list, tuple)):
            stack.extend(owner)
        elif hasattr(owner, "__dict__") and type(owner).__module__.startswith("cityshade"):
            stack.extend(vars(owner).values())
    return total


def _moved_to(camera: Camera, source: City, target: City) -> Camera:
    """A camera of one map's city in another's scene (both in the same UTM zone, shifted origins)."""
    import pyproj

    to_metres = pyproj.Transformer.from_crs("EPSG:4326", target.crs, always_xy=True)
    if source.crs != target.crs:
        raise CityshadeError("the tiled extract and its source are in different projections", exit_code=2)
    (sx, sy), (tx, ty) = (to_metres.transform(*city.origin) for city in (source, target))
    shift = np.array([sx - tx, 0.0, -(sy - ty)])  # map north is scene -z
    return Camera(
        tuple(camera.eye + shift),
        tuple(np.asarray(camera.target) + shift),
        fov_y=camera.fov_y,
        near=camera.near,
        far=camera.far,
    )


def _city(source: str, count: int, extract: str | None, helsinki: City | None = None) -> City:
    """The city to measure; a tiled extract (buildings only) gets `helsinki`'s street camera, moved."""
    if source == "generator":
        return default_city(blocks=BLOCKS[count])
    from ..maps import load_map, map_city

    city = map_city(load_map(extract))
    if "street" not in city.viewpoints:
        city.viewpoints["street"] = _moved_to(helsinki.camera("street"), helsinki, city)
    return city


def _helsinki() -> City:
    from ..maps import load_map, map_city

    return map_city(load_map(HELSINKI))


def _aerial(city: City, t: float) -> Camera:
    """The aerial viewpoint panned sideways across AERIAL_PAN of the city's width."""
    start = city.camera("aerial")
    view = np.asarray(start.target, float) - start.eye
    side = np.cross(view, [0.0, 1.0, 0.0])
    side /= np.linalg.norm(side)
    eye = start.eye + side * AERIAL_PAN * (city.bounds[2] - city.bounds[0]) * t
    return Camera(tuple(eye), tuple(eye + view), fov_y=start.fov_y, near=start.near, far=start.far)


CAMERA_PATHS = {"street": PATHS["walk"], "aerial": _aerial}


def _draws(renderer: Renderer, city: City, frames: int, suffix: str = "") -> dict:
    def path(name):
        return lambda i: renderer.draw(CAMERA_PATHS[name](city, min(1.0, i / max(frames, 1))))

    return {name + suffix: path(name) for name in CAMERA_PATHS}


def _viewer_fps(city: City, settings: RenderSettings, frames: int) -> dict:
    """Walks the street of `city` in the viewer's own draw path (a headless window) with the target
    frame rate on: fps over the frames drawn at the scale and quality steps it settled on (the
    first of them, which allocates the targets or compiles the programs, left out where there are more)."""
    from ..render import quality_status
    from ..viewer import open_viewer

    viewer = open_viewer(city, "street", settings, window="headless", size=SIZE, target_fps=TARGET_FPS)
    try:
        viewer.press("W")
        seconds, states = [], []
        for k in range(frames):
            viewer.wnd.use()
            viewer.on_render(0.1 * k, seconds[-1] if seconds else 0.1)
            seconds.append(viewer.frame_times[-1])
            states.append((viewer.renderer.size, viewer.resolution.level))
        settled = [s for s, state in zip(seconds, states) if state == states[-1]]
        counted = settled[1:] if len(settled) > 1 else settled
        return {
            "fps": 1.0 / statistics.median(counted),
            "scale": viewer.resolution.scale,
            "quality_steps": quality_status(viewer.resolution.level).strip(),
            "internal_size": list(states[-1][0]),
            "frames": frames,
            "frames_counted": len(counted),
            "frame_ms": [round(s * 1e3, 1) for s in seconds],
        }
    finally:
        viewer.renderer.release()
        viewer.wnd.destroy()


def grammar_cache_frames(city: City, frames: int, size: tuple[int, int] = SIZE) -> dict:
    """The first `frames` frames (and one warm-up) of the full run's street walk drawn with the grammar
    cache and without, in turn in one context: their frame times in seconds, the cache's counts after
    each frame, and the uncached median over the cached one."""
    settings = RenderSettings(samples=0)
    renderers = {"cached": Renderer(size, settings.with_(grammar_cache=True))}
    renderers["uncached"] = Renderer(size, settings.with_(grammar_cache=False), ctx=renderers["cached"].ctx)
    counts = []

    def draw(renderer: Renderer):
        def frame(i: int):
            renderer.draw(CAMERA_PATHS["street"](city, min(1.0, i / FULL_FRAMES)))
            if renderer is renderers["cached"]:
                counts.append(renderer.textures.grammar_pass.cache.stats)

        return frame

    try:
        for renderer in renderers.values():
            renderer.set_city(city)
        timing = time_interleaved(renderers["cached"].ctx, {k: draw(r) for k, r in renderers.items()}, frames)
    finally:
        for renderer in renderers.values():
            renderer.release()
    seconds = {name: list(t.samples) for name, t in timing.items()}
    speedup = statistics.median(seconds["uncached"]) / statistics.median(seconds["cached"])
    return {"frames": seconds, "cache": counts, "speedup": round(speedup, 3)}


def street_profile(renderer: Renderer, city: City) -> dict[str, float]:
    """Milliseconds per pass of the street walk's first view, the median of PROFILE_FRAMES frames,
    each pass timed on its own (ctx.finish() around it), slowest first; 'frame' their sum."""
    camera = CAMERA_PATHS["street"](city, 0.0)
    times = []
    for _ in range(PROFILE_FRAMES):
        renderer.draw(camera, profile=True)
        times.append(renderer.last_pass_seconds)
    median = {name: round(1e3 * statistics.median(t[name] for t in times), 1) for name in times[0]}
    ordered = dict(sorted(median.items(), key=lambda item: -item[1]))
    return {**ordered, "frame": round(sum(ordered.values()), 1)}


def culled_pixels_differing(renderer: Renderer, city: City) -> dict[str, int]:
    """Per view of CULLING_VIEWS: pixels that differ between culling="gpu" and culling="off" (what
    GPU culling leaves out must be hidden: 0 expected). The renderer holds `city`."""
    settings = renderer.settings
    differing = {}
    try:
        for view in CULLING_VIEWS:
            images = []
            for culling in ("gpu", "off"):
                renderer.set_settings(settings.with_(culling=culling))
                for _ in range(SETTLE_FRAMES):  # the last frame's shadow cascades all drawn from this view
                    image = renderer.render(city.camera(view))
                images.append(image)
            differing[view] = int(np.any(images[0] != images[1], axis=-1).sum())
    finally:
        renderer.set_settings(settings)
    return differing


def loaded_city(renderer: Renderer, make_city) -> tuple[City, float, int]:
    """(the city `make_city()` builds, seconds to build and upload it, resident bytes it added to the
    process): the load time and memory of `measure_city`."""
    release_freed_memory()  # as set_city does at its end: else the pages freed before are counted against the city
    resident = _resident_bytes()
    start = time.perf_counter()
    city = make_city()
    renderer.set_city(city)
    return city, time.perf_counter() - start, _resident_bytes() - resident


def measure_city(
    source: str,
    count: int,
    frames: int,
    extract: str | None = None,
    reference: str | None = None,
    viewer_frames: int = 0,
) -> dict:
    """One city's load time, memory and frame times (see the module's text), as a JSON-able dict."""
    settings = RenderSettings(samples=0)
    renderer = Renderer(SIZE, settings)
    helsinki = _helsinki() if source == "osm" else None  # for its street camera: not part of the city measured
    city, load_seconds, resident = loaded_city(renderer, lambda: _city(source, count, extract, helsinki))
    gpu_bytes = _buffer_bytes(renderer.city, renderer.trees)
    draws = _draws(renderer, city, frames)
    others = []
    if reference is not None or (source == "generator" and count != COUNTS[0]):
        small = _city(source, COUNTS[0], reference, helsinki)
        others.append(Renderer(SIZE, settings))
        others[0].set_city(small)
        draws.update(_draws(others[0], small, frames, suffix="_1k"))
    timing = time_interleaved(renderer.ctx, draws, frames, warmup=1)
    for other in others:
        other.release()
    profile = street_profile(renderer, city) if viewer_frames else None
    out = {
        "source": source,
        "buildings": len(city.masses),
        "load_seconds": load_seconds,
        "resident_bytes": resident,
        "gpu_buffer_bytes": gpu_bytes,
        "device": renderer.device,
        "frames": {name: list(t.samples) for name, t in timing.items()},
        "culled_pixels_differing": culled_pixels_differing(renderer, city) if count == COUNTS[0] else None,
    }
    if profile is not None:
        out["street_profile_ms"] = profile
    renderer.release()
    if source == "generator" and count == COUNTS[0]:
        out["grammar_cache"] = grammar_cache_frames(city, frames)
    if viewer_frames:
        out["viewer"] = _viewer_fps(city, settings, viewer_frames)
    return out


def _measured(arguments: dict) -> dict:
    """measure_city(**arguments) in a fresh Python process: its memory is the city's alone."""
    code = (
        "import json, sys; from cityshade.bench.scale import measure_city; "
        "print(json.dumps(measure_city(**json.loads(sys.argv[1]))))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, json.dumps(arguments)], capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        raise CityshadeError(
            f"bench scale: measuring {arguments['source']} at {arguments['count']} buildings "
            f"failed: {lines[-1] if lines else 'no output'}"
        )
    return json.loads(done.stdout.strip().splitlines()[-1])


# -- the benchmark ------------------------------------------------------------------------------------


def _seconds(samples) -> list[float]:
    """[median, 95th percentile, interquartile range] in seconds."""
    q1, median, q3, p95 = np.percentile(samples, [25, 50, 75, 95])
    return [round(float(median), 3), round(float(p95), 3), round(float(q3 - q1), 3)]


def _bytes_per_building(run: dict) -> float:
    """Resident bytes the city added per building, plus its GPU buffers where those are not already
    in the process's memory (a software rasteriser keeps them there)."""
    software = any(name in run["device"].lower() for name in ("llvmpipe", "softpipe", "swrast"))
    return (run["resident_bytes"] + (0 if software else run["gpu_buffer_bytes"])) / run["buildings"]


def run(quick: bool, out_dir: Path) -> BenchResult:
    if not HELSINKI.is_file():
        raise CityshadeError(f"{HELSINKI} is missing: run `make data` to fetch the OpenStreetMap extracts", exit_code=2)
    from ..maps import tiled_extract

    frames = QUICK_FRAMES if quick else FULL_FRAMES
    osm_counts = COUNTS[:2] if quick else COUNTS
    runs = []
    with tempfile.TemporaryDirectory() as folder:
        extracts = {}
        for count in osm_counts:
            extracts[count] = str(Path(folder) / f"tiled-{count}.osm.pbf")
            tiled_extract(HELSINKI, extracts[count], count)
        for count in COUNTS:
            runs.append(
                _measured(
                    {
                        "source": "generator",
                        "count": count,
                        "frames": frames,
                        "viewer_frames": VIEWER_FRAMES[quick] if count == COUNTS[-1] else 0,
                    }
                )
            )
        for count in osm_counts:
            runs.append(
                _measured(
                    {
                        "source": "osm",
                        "count": count,
                        "frames": frames,
                        "extract": extracts[count],
                        "reference": extracts[COUNTS[0]] if count != COUNTS[0] else None,
                    }
                )
            )
    return _result(runs, frames, quick, osm_counts)


def _result(runs: list[dict], frames: int, quick: bool, osm_counts) -> BenchResult:
    biggest = next(r for r in runs if r["source"] == "generator" and r["buildings"] > 90_000)
    culled = {r["source"]: r["culled_pixels_differing"] for r in runs if r["culled_pixels_differing"] is not None}
    cache = next(r["grammar_cache"] for r in runs if "grammar_cache" in r)
    result = ScaleResult(biggest["device"], {})
    record = dict(cull_back_faces=True, depth_prepass=True, frustum_culling=True, msaa=0, size=SIZE)
    result.methods = {
        "street": method_record(**record, path="walk: 60 m down the 'street' viewpoint's street"),
        "aerial": method_record(**record, path=f"the 'aerial' viewpoint panned {AERIAL_PAN:.0%} of the city's width"),
        "street_1k": method_record(
            **record,
            path="the same walk in the 1,000-building city of the same source, "
            "its frames taking turns with the big city's",
        ),
        "aerial_1k": method_record(**record, path="the same pan in the 1,000-building city"),
    }
    result.timing = {
        **timing_record(frames),
        "frames_per_path": frames,
        "quick": quick,
        "statistic": "median and 95th percentile; spread: interquartile range (q3 - q1)",
    }
    for r in runs:
        f = r["frames"]
        r["ratios"] = {
            name: (
                round(statistics.median(f[name]) / statistics.median(f[name + "_1k"]), 3) if name + "_1k" in f else 1.0
            )
            for name in CAMERA_PATHS
        }
    for name in CAMERA_PATHS:
        result.add_table(
            f"Frame time, {name} path, {SIZE[0]}x{SIZE[1]}, no MSAA, {frames} frames",
            ["city", "buildings", "median s", "p95 s", "IQR s", "over 1k (interleaved)"],
            [[r["source"], r["buildings"], *_seconds(r["frames"][name]), r["ratios"][name]] for r in runs],
        )
    result.add_table(
        "Load time and memory",
        ["city", "buildings", "load s", "resident MB (city)", "GPU buffers MB", "bytes per building"],
        [
            [
                r["source"],
                r["buildings"],
                round(r["load_seconds"], 2),
                round(r["resident_bytes"] / 1e6, 1),
                round(r["gpu_buffer_bytes"] / 1e6, 1),
                round(_bytes_per_building(r)),
            ]
            for r in runs
        ],
    )
    beside = [list(row) for row in TODAY]
    beside += [
        [
            f"{r['source']}, this run",
            r["buildings"],
            _seconds(r["frames"]["street"])[0],
            _seconds(r["frames"]["aerial"])[0],
        ]
        for r in runs
    ]
    beside.append([PAPER[0], PAPER[1], PAPER[2], PAPER[2]])
    result.add_table(
        "Beside today's numbers and the paper's (median s per frame)",
        ["renderer", "buildings", "street", "aerial"],
        beside,
    )
    result.add_table(
        f"Pixels differing between culling 'gpu' and 'off', 1,000-building cities, {SIZE[0]}x{SIZE[1]}",
        ["city", *CULLING_VIEWS],
        [[source, *(views[v] for v in CULLING_VIEWS)] for source, views in culled.items()],
    )
    viewer = biggest["viewer"]
    result.add_table(
        f"Viewer walking the street, target {TARGET_FPS:g} fps (headless, {SIZE[0]}x{SIZE[1]} window)",
        ["buildings", "fps", "final scale", "quality steps", "internal size", "frames (counted)"],
        [
            [
                biggest["buildings"],
                round(viewer["fps"], 2),
                viewer["scale"],
                viewer["quality_steps"] or "none",
                "x".join(map(str, viewer["internal_size"])),
                f"{viewer['frames']} ({viewer['frames_counted']})",
            ]
        ],
    )
    result.add_table(
        f"Per pass, the {biggest['buildings']:,}-building street view, {SIZE[0]}x{SIZE[1]}, no MSAA "
        f"(median of {PROFILE_FRAMES} frames, each pass timed on its own)",
        ["pass", "ms"],
        [[name, ms] for name, ms in biggest["street_profile_ms"].items()],
    )
    result.ratios.update(
        {
            "street_100k_over_1k": biggest["ratios"]["street"],
            "aerial_100k_over_1k": biggest["ratios"]["aerial"],
            "grammar_cache_speedup": cache["speedup"],
            "bytes_per_building": round(_bytes_per_building(biggest)),
            "culled_pixels_differing": sum(culled["generator"].values()),
            "viewer_fps_llvmpipe": round(viewer["fps"], 2),
        }
    )
    result.targets.update(
        {
            "street_100k_over_1k": "<= 1.3",
            "aerial_100k_over_1k": "<= 2.5",
            "grammar_cache_speedup": ">= 2",
            "bytes_per_building": "<= 2048",
            "culled_pixels_differing": "== 0",
            "viewer_fps_llvmpipe": ">= 10",
        }
    )
    result.notes.append(
        f"Ratios from the generator city of {biggest['buildings']:,} buildings over the "
        "1,000-building one, frames interleaved in one process; the OpenStreetMap rows likewise."
    )
    result.notes.append(
        "culled_pixels_differing: the 1,000-building generator city's street and aerial views "
        "drawn with culling='gpu' and culling='off', pixels that differ summed over both."
    )
    result.notes.append(
        f"grammar_cache_speedup: the 1,000-building generator city's street walk, its first {frames} "
        "frames of the full run's 60 (1 m apart) after one warm-up frame, drawn with "
        "RenderSettings(grammar_cache=True) and False in turn; median uncached over median cached "
        f"(cached {_seconds(cache['frames']['cached'])[0]} s, uncached {_seconds(cache['frames']['uncached'])[0]} s)."
    )
    result.notes.append(
        "bytes_per_building: resident memory the city added (masses, meshes, trees, and on this "
        "software rasteriser its GPU buffers too) per building; GPU buffers are added on a hardware GPU."
    )
    if quick:
        result.notes.append(
            f"Quick run: {frames} frames per path instead of {FULL_FRAMES}, viewer {VIEWER_FRAMES[True]} "
            f"frames; OpenStreetMap tiled to {', '.join(f'{c:,}' for c in osm_counts)} buildings only."
        )
    result.notes.append(
        "The tiled extract holds Helsinki's buildings only (no streets, trees or ground): its street "
        "camera is Helsinki's own, in the first tile. Map data © OpenStreetMap contributors, ODbL 1.0."
    )
    for name, why in result.missing.items():
        result.notes.append(f"{name}: not measured: {why}.")
    return result
