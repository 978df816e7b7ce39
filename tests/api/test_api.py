"""The Python API: cityshade.render_image returns the picture as a numpy array."""

from __future__ import annotations

import numpy as np
import pytest

import cityshade
from cityshade.errors import UsageError
from cityshade.render import Renderer, RenderSettings
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


@pytest.mark.parametrize("lights", [2, -0.1, "a", float("nan"), True])
def test_render_settings_refuse_a_share_of_lit_rooms_outside_0_to_1(lights):
    with pytest.raises(UsageError, match=r"^invalid --lights .+; the share of lit rooms is a number from 0 to 1$"):
        RenderSettings(lights=lights)
    assert RenderSettings(lights="0.25").lights == 0.25  # the command line's text, as a number


def test_render_image_refuses_a_time_that_is_no_time_of_day():
    with pytest.raises(UsageError, match=r"^invalid time 1910; use HH:MM from 00:00 to 23:59"):
        cityshade.render_image("interior", camera="corner", size=(16, 12), time=1910)


@pytest.mark.parametrize("bad", [24.0, -1, float("nan"), True, "25:00", "noon"])
def test_one_time_type_throughout_the_api(bad):
    """Every time takes "HH:MM" or hours, through one parser, with one message for anything else."""
    assert RenderSettings(time_of_day="18:30").time_of_day == RenderSettings(time_of_day=18.5).time_of_day == 18.5
    assert RenderSettings().with_(time_of_day="06:15").time_of_day == 6.25
    with pytest.raises(UsageError, match=r"^invalid time .+; use HH:MM from 00:00 to 23:59, e\.g\. 18:50, or hours"):
        RenderSettings(time_of_day=bad)
    with pytest.raises(UsageError, match=r"^invalid time "):
        cityshade.render_image("interior", camera="corner", size=(16, 12), time=bad)


@pytest.mark.parametrize(
    ("name", "seed", "message"),
    [
        ("grid", "x", r"^invalid --seed 'x'; a seed is a whole number from 0 to 2147483647$"),
        ("grid", -1, r"^invalid --seed -1; a seed is a whole number"),
        (["grid"], None, r"^unknown city \['grid'\]; allowed: default, "),
    ],
)
def test_make_city_refuses_a_bad_name_or_seed(name, seed, message):
    with pytest.raises(UsageError, match=message):
        make_city(name, seed)


def test_the_renderer_refuses_what_is_not_a_city_or_a_camera(gl_context):
    renderer = Renderer((16, 12), RenderSettings(samples=0, trees=False), ctx=gl_context)
    try:
        with pytest.raises(UsageError, match=r"^invalid city 'grid'; Renderer.set_city takes a City"):
            renderer.set_city("grid")
        renderer.set_city(make_city("interior"))
        for draw in (renderer.render_ids, renderer.render):
            with pytest.raises(UsageError, match=r"^invalid camera None; give a Camera"):
                draw(None)
    finally:
        renderer.release()
