"""Cities in a notebook: cityshade.show returns what Jupyter displays inline (_repr_png_), and
cityshade.view_widget is the city in a jupyter_rfb widget, driven here by its events, headless."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

import cityshade
from cityshade.errors import UsageError
from cityshade.scene import Camera, make_city

SIZE = (48, 32)


def _decoded(picture) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(picture._repr_png_())))


def test_show_an_image_is_displayed_as_that_png():
    image = np.random.default_rng(0).integers(0, 255, (12, 20, 3), dtype=np.uint8)
    picture = cityshade.show(image)
    assert np.array_equal(_decoded(picture), image) and np.asarray(picture).shape == (12, 20, 3)
    with pytest.raises(UsageError, match=r"^cannot show an array of shape \(12, 20\) and dtype float64"):
        cityshade.show(np.zeros((12, 20)))
    with pytest.raises(UsageError, match="are for a city, not an image"):
        cityshade.show(image, size=SIZE)


@pytest.mark.gl
def test_show_a_city_from_a_camera_is_its_render():
    camera = Camera((30.0, 20.0, 40.0), (0.0, 5.0, 0.0), fov_y=50.0, near=0.3, far=100_000.0)
    picture = cityshade.show("interior", camera=camera, size=SIZE, time=13.5)
    expected = cityshade.render_image("interior", camera=camera, size=SIZE, time="13:30")
    assert np.array_equal(_decoded(picture), expected)
    assert expected.std() > 10


@pytest.mark.gl
def test_view_widget_renders_and_orbits_on_its_events():
    pytest.importorskip("jupyter_rfb")
    widget = cityshade.view_widget("interior", camera="overview", size=SIZE, time="12:00")
    first = widget.get_frame()
    assert np.array_equal(first, cityshade.render_image("interior", camera="overview", size=SIZE, time=12.0))
    start = widget.camera
    widget.handle_event({"event_type": "pointer_down", "x": 10, "y": 10, "buttons": [1]})
    widget.handle_event({"event_type": "pointer_move", "x": 40, "y": 10, "buttons": [1]})
    widget.handle_event({"event_type": "pointer_up", "x": 40, "y": 10})
    turned = widget.camera
    radius = lambda c: np.linalg.norm(np.subtract(c.eye, c.target))  # noqa: E731
    assert turned.target == start.target and radius(turned) == pytest.approx(radius(start))
    assert turned.eye[1] == pytest.approx(start.eye[1])  # dragged sideways: round the vertical axis only
    assert not np.array_equal(widget.get_frame(), first)
    widget.handle_event({"event_type": "wheel", "dx": 0, "dy": 200, "x": 0, "y": 0})
    assert radius(widget.camera) == pytest.approx(radius(start) * 1.0015**200)
    widget.handle_event({"event_type": "resize", "width": 40, "height": 24, "pixel_ratio": 1})
    assert widget.get_frame().shape == (24, 40, 3)
    widget.handle_event({"event_type": "close"})


def test_view_widget_refuses_unknown_settings():
    pytest.importorskip("jupyter_rfb")
    with pytest.raises(UsageError, match="unknown render setting 'colour'"):
        cityshade.view_widget(make_city("interior"), colour=1)
