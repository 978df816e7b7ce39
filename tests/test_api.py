"""The Python API: cityshade.render_image returns the picture as a numpy array."""

from __future__ import annotations

import numpy as np
import pytest

import cityshade
from cityshade.scene import make_city

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def test_render_returns_an_rgb_uint8_array():
    image = cityshade.render_image("interior", camera="corner", size=(64, 48), lights=0.7)
    assert image.shape == (48, 64, 3) and image.dtype == np.uint8
    assert image.std() > 10


def test_render_accepts_a_city_and_the_time_changes_the_sky():
    city = cityshade.make_city("interior")
    noon = cityshade.render_image(city, camera="overview", size=(64, 48), time="12:00")
    night = cityshade.render_image(city, camera="overview", size=(64, 48), time="22:30")
    assert noon[:8].mean() > night[:8].mean() + 30  # the sky at the top of the frame


@pytest.mark.parametrize("camera", sorted(make_city("interior").viewpoints))
def test_every_interior_camera_renders(camera):
    image = cityshade.render_image("interior", camera=camera, size=(64, 48), samples=0).astype(int)
    assert image.std() > 5, f"{camera}: a flat picture"


def test_the_render_package_is_a_plain_package():
    import cityshade.render._frame  # the package is not hidden by a function of the same name

    assert cityshade.render._frame.frame_passes is cityshade.render.frame_passes
    assert not callable(cityshade.render)  # the image function is cityshade.render_image
