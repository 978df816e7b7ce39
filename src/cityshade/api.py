"""The Python API: `cityshade.render(...)` and friends."""

from __future__ import annotations

import statistics

import numpy as np

from .errors import UsageError
from .render import Renderer, RenderSettings, guessed_aov, parse_time
from .scene import City, make_city


def render_city(city: str | City = "default", seed: int | None = None, camera: str = "street",
                size: tuple[int, int] = (1280, 720), lights: float | None = None, time: str = "19:10",
                interior_mapping: bool = True, frames: int = 3, aov: str | None = None,
                **settings) -> tuple[np.ndarray, dict]:
    """Renders a named city (or a City); returns the HxWx3 uint8 image and facts about the frame
    (its median time over `frames` frames after a first one that compiles and uploads).
    aov="guessed" tints the buildings by what the map gave and what was guessed (render/_guessed.py)."""
    if aov not in (None, "guessed"):
        raise UsageError(f"unknown aov {aov!r}; allowed: guessed")
    layout = city if isinstance(city, City) else make_city(city, seed)
    view = layout.camera(camera)
    renderer = Renderer(size, RenderSettings(lights=lights, time_of_day=parse_time(time),
                                             interior_mapping=interior_mapping, **settings))
    try:
        renderer.set_city(layout)
        image = renderer.render(view)  # the first frame compiles shaders and uploads: not timed
        times = []
        for _ in range(frames):
            image = renderer.render(view)
            times.append(renderer.last_frame_seconds)
        if aov == "guessed":
            image = guessed_aov(image, renderer.render_ids(view), layout.masses)
        info = {"frame_ms": statistics.median(times) * 1000 if times else float("nan"), "frames": frames,
                "device": renderer.device, "buildings": len(layout.masses), "samples": renderer.samples,
                "trees": len(renderer.trees.trees) if renderer.trees is not None else 0}
    finally:
        renderer.release()
    return image, info


def render(city: str | City = "default", **kwargs) -> np.ndarray:
    """The city as an HxWx3 uint8 numpy array. Keywords as `render_city`."""
    return render_city(city, frames=0, **kwargs)[0]
