"""Cities in a notebook: `show` returns a Picture, which Jupyter (IPython's display) draws inline
through its `_repr_png_`; `view_widget` is the city in a jupyter_rfb remote frame buffer widget,
rendered headless on the kernel's side and turned by dragging (orbit) and the wheel (distance).
jupyter_rfb is the optional `notebook` extra; nothing else here needs a display."""

from __future__ import annotations

import functools
import io
from pathlib import Path

import numpy as np
from PIL import Image

from ..errors import UsageError
from ..render import Renderer, RenderSettings
from ..scene import Camera, City, make_city
from ._render import render_image

DRAG_DEGREES = 0.4  # per pixel dragged
WHEEL_FACTOR = 1.0015  # distance change per wheel unit


class Picture:
    """An HxWx3 uint8 image that Jupyter displays inline; `array` holds it, `save(path)` writes a PNG."""

    def __init__(self, array: np.ndarray):
        array = np.asarray(array)
        if array.ndim != 3 or array.shape[2] not in (3, 4) or array.dtype != np.uint8:
            raise UsageError(f"cannot show an array of shape {array.shape} and dtype {array.dtype}; give HxWx3 uint8")
        self.array = array

    def _repr_png_(self) -> bytes:
        buffer = io.BytesIO()
        Image.fromarray(self.array).save(buffer, format="PNG")
        return buffer.getvalue()

    def __array__(self, dtype=None, copy=None):
        return self.array if dtype is None else self.array.astype(dtype)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.array.shape

    def save(self, path: str | Path) -> Path:
        Path(path).write_bytes(self._repr_png_())
        return Path(path)

    def __repr__(self) -> str:
        return f"Picture({self.array.shape[1]}x{self.array.shape[0]})"


def show(what: np.ndarray | str | City = "default", camera: str | Camera = "street", **render) -> Picture:
    """A rendered image (HxWx3 uint8), or a city (by name or a City) seen from `camera` (a viewpoint's
    name or a Camera) rendered with `render_image`'s keywords, as a Picture Jupyter shows inline."""
    if isinstance(what, np.ndarray):
        if render:
            raise UsageError(f"render settings {', '.join(sorted(render))} are for a city, not an image")
        return Picture(what)
    return Picture(render_image(what, camera=camera, **render))


def _orbit(camera: Camera, yaw: float, pitch: float, scale: float) -> Camera:
    """The camera turned about its target by yaw (about the vertical) and pitch, its distance scaled."""
    eye, target = np.asarray(camera.eye, float), np.asarray(camera.target, float)
    offset = (eye - target) * scale
    distance = np.linalg.norm(offset)
    heading = np.arctan2(offset[0], offset[2]) + np.radians(yaw)
    elevation = np.clip(np.arcsin(offset[1] / distance) + np.radians(pitch), np.radians(-5), np.radians(89))
    turned = distance * np.array(
        [np.cos(elevation) * np.sin(heading), np.sin(elevation), np.cos(elevation) * np.cos(heading)]
    )
    return Camera(tuple(target + turned), camera.target, camera.fov_y, camera.near, camera.far)


@functools.cache
def _widget_class():
    try:
        from jupyter_rfb import RemoteFrameBuffer
    except ImportError:
        raise UsageError("view_widget needs jupyter_rfb: pip install 'cityshade[notebook]'") from None

    class CityWidget(RemoteFrameBuffer):
        """A city in a notebook: each frame rendered headless at the widget's size (jupyter_rfb
        sends it to the page); drag to orbit the target, the wheel to come closer or go away."""

        def __init__(self, city: City, camera: Camera, size, settings: RenderSettings, **kwargs):
            super().__init__(css_width=f"{size[0]}px", css_height=f"{size[1]}px", **kwargs)
            self.city, self.camera, self.settings = city, camera, settings
            self.renderer = Renderer(size, settings)
            self.renderer.set_city(city)
            self._dragging = None

        def get_frame(self) -> np.ndarray:
            return self.renderer.render(self.camera)

        def handle_event(self, event: dict):
            kind = event.get("event_type")
            if kind == "resize":
                self.renderer.resize((max(1, int(event["width"])), max(1, int(event["height"]))))
            elif kind == "pointer_down":
                self._dragging = (event["x"], event["y"])
            elif kind == "pointer_move" and self._dragging is not None:
                dx, dy = event["x"] - self._dragging[0], event["y"] - self._dragging[1]
                self._dragging = (event["x"], event["y"])
                self.camera = _orbit(self.camera, -dx * DRAG_DEGREES, dy * DRAG_DEGREES, 1.0)
            elif kind == "pointer_up":
                self._dragging = None
            elif kind == "wheel":
                self.camera = _orbit(self.camera, 0.0, 0.0, WHEEL_FACTOR ** event.get("dy", 0.0))
            elif kind == "close":
                self.renderer.release()
                return
            else:
                return
            self.request_draw()

    return CityWidget


def view_widget(
    city: str | City = "default",
    camera: str | Camera = "aerial",
    size=(640, 360),
    time: str | float = "12:00",
    **settings,
):
    """The city as a jupyter_rfb widget (display it as a cell's last value): drag to orbit, wheel to zoom."""
    from .._values import check_size, parse_time

    unknown = sorted(set(settings) - set(RenderSettings.__dataclass_fields__))
    if unknown:
        raise UsageError(f"unknown render setting {unknown[0]!r}; see cityshade.RenderSettings")
    layout = city if isinstance(city, City) else make_city(city)
    view = camera if isinstance(camera, Camera) else layout.camera(camera)
    return _widget_class()(layout, view, check_size(size), RenderSettings(time_of_day=parse_time(time), **settings))
