"""The Python API: `cityshade.render_image(...)` and `cityshade.render_city(...)`."""

from __future__ import annotations

import statistics
from time import perf_counter

import numpy as np

from .._values import check_lights, check_samples, check_seed, check_size, parse_time
from ..errors import UsageError
from ..render import Renderer, RenderSettings, TileCache, guessed_aov
from ..scene import Camera, City, make_city

AOVS = ("guessed", "class", "instance", "depth")  # what `aov` may name instead of the picture


def render_city(
    city: str | City = "default",
    seed: int | None = None,
    camera: str | Camera = "street",
    size: tuple[int, int] = (1280, 720),
    lights: float | None = None,
    time: str | float = "19:10",
    interior_mapping: bool = True,
    frames: int = 3,
    profile: bool = False,
    aov: str | None = None,
    tiles: TileCache | None = None,
    memory_budget: int | None = None,
    **settings,
) -> tuple[np.ndarray, dict]:
    """Renders a named city (or a City); returns the HxWx3 uint8 image and facts about the frame
    (its median time over `frames` frames after a first one that compiles and uploads). With
    `profile`, info["pass_ms"] holds each pass's median time, in the order the passes run;
    info["city_s"] the seconds the city took to mesh (or stream in) and upload.
    aov="guessed" tints the buildings by what the map gave and what was guessed (render/_guessed.py);
    the other AOVs return another array in the picture's place, from the same camera at the same size:
    "class" HxW uint8 dataset class ids (info["classes"]: id -> name, dataset.CLASSES), "instance"
    HxW uint16 building index + 1 (0: no building), "depth" HxW float32 camera-space z in metres
    (+inf where nothing was drawn), all from the id AOV's pass (dataset.class_image, instance_image).
    `tiles` (a tile cache, render.open_tiles) draws its city instead, streamed with at most
    `memory_budget` bytes of tiles resident (None: all); the first frame waits for the tiles its
    view needs. `camera` is one of the city's viewpoints by name or a Camera; `time` is "HH:MM" or
    hours. Bad arguments raise UsageError with the message the command line prints."""
    if aov not in (None, *AOVS):
        raise UsageError(f"unknown aov {aov!r}; allowed: {', '.join(AOVS)}")
    size, lights = check_size(size), check_lights(lights)
    seed = None if seed is None else check_seed(seed)
    if "samples" in settings:
        settings["samples"] = check_samples(settings["samples"])
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 0:
        raise UsageError(f"invalid frames {frames!r}; a whole number of timed frames, 0 or more")
    unknown = sorted(set(settings) - set(RenderSettings.__dataclass_fields__))
    if unknown:
        raise UsageError(f"unknown render setting {unknown[0]!r}; see cityshade.RenderSettings")
    if tiles is not None:
        layout = tiles.city
    else:
        layout = city if isinstance(city, City) else make_city(city, seed)
    view = camera if isinstance(camera, Camera) else layout.camera(camera)
    renderer = Renderer(
        size, RenderSettings(lights=lights, time_of_day=parse_time(time), interior_mapping=interior_mapping, **settings)
    )
    try:
        start = perf_counter()
        if tiles is not None:
            renderer.set_tiles(tiles, memory_budget)
        else:
            renderer.set_city(layout)
        renderer.wait_for_tiles(view)
        city_seconds = perf_counter() - start
        image = renderer.render(view)  # the first frame compiles shaders and uploads: not timed
        times, passes = [], {}
        for _ in range(frames):
            image = renderer.draw(view, profile=profile).read()[..., :3].copy()
            times.append(renderer.last_frame_seconds)
            for name, seconds in renderer.last_pass_seconds.items():
                passes.setdefault(name, []).append(seconds)
        if aov == "guessed":
            image = guessed_aov(image, renderer.render_ids(view), layout.masses)
        elif aov is not None:
            image = _aov_array(aov, renderer, view)
        info = {
            "frame_ms": statistics.median(times) * 1000 if times else float("nan"),
            "frames": frames,
            "device": renderer.device,
            "buildings": len(layout.masses),
            "samples": renderer.samples,
            "trees": len(renderer.trees.trees) if renderer.trees is not None else 0,
            "pass_ms": {name: statistics.median(s) * 1000 for name, s in passes.items()},
            "city_s": city_seconds,
        }
        if aov == "class":
            from ..dataset import CLASSES  # the dataset reads maps: loaded only when asked for

            info["classes"] = {str(i): name for i, name in enumerate(CLASSES)}
        if tiles is not None:
            streamer = renderer.city.streamer
            info["tiles"] = {
                "resident": len(streamer.resident),
                "total": len(tiles.tiles),
                "resident_bytes": streamer.resident_bytes,
            }
    finally:
        renderer.release()
    return image, info


def _aov_array(aov: str, renderer: Renderer, view) -> np.ndarray:
    from ..dataset import class_image, instance_image, linear_depth

    ids = renderer.render_ids(view)
    if aov == "class":
        return class_image(ids)
    if aov == "instance":
        instances = instance_image(ids)
        if instances.max(initial=0) > np.iinfo(np.uint16).max:
            raise UsageError(f"--aov instance: {int(instances.max())} buildings do not fit a 16-bit PNG (65,535)")
        return instances.astype(np.uint16)
    return linear_depth(renderer.depth(aov=True), view.near, view.far)


def render_image(city: str | City = "default", **kwargs) -> np.ndarray:
    """The city as an HxWx3 uint8 numpy array. Keywords as `render_city`."""
    return render_city(city, frames=0, **kwargs)[0]
