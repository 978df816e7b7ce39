"""Exposure and the tone map (shaders/frame/tonemap.glsl) against a numpy twin, pixel by pixel:
the display image is the resolved HDR frame times the time of day's exposure, through the ACES
curve and sRGB encoding. God rays are off here (tests/test_trees_scene.py covers them)."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.render import Daylight, Renderer, RenderSettings
from cityshade.scene import make_city
from render_checks import render_finite

SIZE = (96, 72)
CITY = make_city("interior")


@pytest.fixture(scope="module")
def renderer(gl_context):
    r = Renderer(SIZE, RenderSettings(samples=0, god_rays=False), ctx=gl_context)
    r.set_city(CITY)
    yield r
    r.release()


def tone_map(hdr: np.ndarray, exposure: float) -> np.ndarray:
    """numpy twin of tonemap.glsl without god rays: exposure, ACES (Narkowicz fit), sRGB, 8 bits."""
    x = hdr.astype(np.float64) * exposure
    aces = np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)
    srgb = np.where(aces < 0.0031308, aces * 12.92, 1.055 * aces ** (1 / 2.4) - 0.055)
    return np.round(srgb * 255)


@pytest.mark.parametrize("hours", [13.0, 21.0])
def test_display_is_the_hdr_frame_tone_mapped_with_the_hours_exposure(renderer, hours):
    renderer.set_settings(renderer.settings.with_(time_of_day=hours))
    image = render_finite(renderer, CITY.camera("overview")).astype(float)
    hdr = renderer.read_hdr()
    exposure = Daylight.at(hours).exposure
    off = np.abs(image - tone_map(hdr, exposure)).max(axis=-1)
    print(
        f"{hours:g} h: exposure {exposure:.2f}; {int((off > 1).sum())} of {off.size} pixels differ from the twin "
        f"by more than 1/255 (max {off.max():.0f})"
    )
    assert (off <= 1).all()
    unexposed = np.abs(image - tone_map(hdr, 1.0)).max(axis=-1) > 1  # the same frame with exposure off
    assert unexposed.mean() > 0.5, "exposure changes the picture"


def test_exposure_follows_the_daylight():
    """The exposure rises from 0.5 by day to 1.3 at night: the tone map lifts the dark scene."""
    noon, night = Daylight.at(13.0), Daylight.at(23.0)
    assert noon.exposure == pytest.approx(0.5, abs=0.05) and night.exposure == pytest.approx(1.3, abs=0.05)
