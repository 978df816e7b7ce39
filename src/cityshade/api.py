"""The Python API: `cityshade.render(...)` and friends."""

from __future__ import annotations

import numpy as np

from .render import Renderer, RenderSettings, parse_time
from .scene import City, make_city


def render_city(city: str | City = "default", seed: int | None = None, camera: str = "street",
                size: tuple[int, int] = (1280, 720), lights: float | None = None, time: str = "19:10",
                interior_mapping: bool = True, **settings) -> tuple[np.ndarray, dict]:
    """Renders a named city (or a City); returns the HxWx3 uint8 image and facts about the frame."""
    layout = city if isinstance(city, City) else make_city(city, seed)
    view = layout.camera(camera)
    renderer = Renderer(size, RenderSettings(lights=lights, time_of_day=parse_time(time),
                                             interior_mapping=interior_mapping, **settings))
    try:
        renderer.set_city(layout)
        renderer.render(view)  # first frame compiles shaders and uploads; time the second
        image = renderer.render(view)
        info = {"frame_ms": renderer.last_frame_seconds * 1000, "device": renderer.device,
                "buildings": len(layout.masses)}
    finally:
        renderer.release()
    return image, info


def render(city: str | City = "default", **kwargs) -> np.ndarray:
    """The city as an HxWx3 uint8 numpy array. Keywords as `render_city`."""
    return render_city(city, **kwargs)[0]
