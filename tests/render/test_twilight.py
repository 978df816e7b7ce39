"""Twilight and night from the sun's depression, measured on small frames of the built-in four-building city:
the night sky is blue-black with an amber town glow low down (before: a maroon-brown dusk glow
dimmed), a white night (the sun 3 degrees down at 60 N in midsummer) stays light, and a twilight
scene stays readable."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.assets import sky_colour
from cityshade.bench.pictures import luminance, measure
from cityshade.dataset import CLASSES, class_image
from cityshade.frame import Daylight
from cityshade.render import Renderer, RenderSettings
from cityshade.render.testing import night_amount
from cityshade.scene import make_city

pytestmark = pytest.mark.gl
SIZE = (96, 54)
NOON = {"sun": (53.0, 180.0)}
WHITE_NIGHT = {"sun": (-3.2, 334.4)}  # Helsinki, 2025-06-21 22:30 (astral)
MIDNIGHT = {"sun": (-52.5, 15.9)}  # Helsinki, 2025-12-21 01:00: no moon


@pytest.fixture(scope="module")
def district(gl_context):
    """One renderer of the built-in four-building city (cheap to set up) for every frame."""
    city = make_city("interior")
    renderer = Renderer(SIZE, RenderSettings(samples=0), ctx=gl_context)
    renderer.set_city(city)
    yield renderer, city
    renderer.release()


def _frame(district, camera, sky):
    renderer, city = district
    renderer.set_settings(renderer.settings.with_(**sky))
    view = city.camera(camera)
    return renderer.render(view), class_image(renderer.render_ids(view))


def _hue(rgb: np.ndarray) -> float:
    import colorsys

    r, g, b = rgb.reshape(-1, 3).astype(float).mean(axis=0) / 255.0
    return colorsys.rgb_to_hsv(r, g, b)[0] * 360.0


def test_twilight_phases_follow_the_sun():
    assert night_amount(-3.0) == 0.0 and night_amount(-6.0) == 0.0  # civil twilight, white nights
    assert 0.4 < night_amount(-12.0) < 0.6 and night_amount(-18.0) == 1.0


def test_the_night_sky_is_blue_with_an_amber_glow_low_down(district):
    rgb, classes = _frame(district, "corner", MIDNIGHT)
    sky = classes == CLASSES.index("sky")
    assert sky.mean() > 0.05
    figures = measure(rgb, classes, np.zeros(classes.shape, np.uint32))
    assert 200.0 < figures["sky_hue"] < 260.0, f"night sky hue {figures['sky_hue']:.0f} (before: maroon-brown)"
    assert figures["sky_luminance"] < 0.02, "night"
    rows = np.nonzero(sky.any(axis=1))[0]
    low = sky & (np.arange(SIZE[1])[:, None] >= rows.max() - 3)  # the sky's lowest rows: the town's glow
    glow = _hue(rgb[low])
    assert 15.0 < glow < 60.0 or 200.0 < glow < 260.0, f"the sky low down has hue {glow:.0f}: maroon or purple"


def test_a_white_night_stays_light_and_readable(district):
    rgb, classes = _frame(district, "corner", WHITE_NIGHT)
    figures = measure(rgb, classes, np.zeros(classes.shape, np.uint32))
    assert figures["sky_luminance"] > 0.12, f"white-night sky luminance {figures['sky_luminance']:.3f}"
    light = Daylight.at(22.5, WHITE_NIGHT["sun"])
    zenith = sky_colour(np.array([0.0, 1.0, 0.0]), light.sky_sun, light.dusk)  # the sun's side glows pink
    assert 190.0 < _hue(np.clip(zenith * 255, 0, 255)) < 250.0, zenith
    day, _ = _frame(district, "overview", NOON)
    dusk, _ = _frame(district, "overview", WHITE_NIGHT)
    ratio = luminance(dusk).mean() / luminance(day).mean()
    assert ratio > 0.25, f"the white-night aerial has {ratio:.0%} of noon's mean luminance"
