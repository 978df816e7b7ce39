"""Exposure and the tone map (shaders/frame/tonemap.glsl) against a numpy twin, pixel by pixel:
the display image is the resolved HDR frame times the time of day's exposure, through the ACES
curve and sRGB encoding, with the god rays' half-resolution radial blur added before it
(render/_godrays.py's numpy twin; tests/trees/test_trees_scene.py checks what they do to a picture)."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.frame import parse_time
from cityshade.render import Daylight, Renderer, RenderSettings
from cityshade.render.testing import god_ray_uniforms, god_rays_reference
from cityshade.scene import make_city
from cityshade.trees import SCENE_TIME, park_scene
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


def test_god_rays_are_their_numpy_twin(gl_context, output_dir):
    """Looking toward the low sun through the park's trees: the display image is the HDR frame plus
    the twin's rays, tone mapped, within 1/255 nearly everywhere (the GPU's bilinear weights are
    quantised, the twin's are exact)."""
    city, hours = park_scene(), parse_time(SCENE_TIME)
    camera = city.camera("park")
    renderer = Renderer(SIZE, RenderSettings(samples=0, time_of_day=hours), ctx=gl_context)
    try:
        renderer.set_city(city)
        image = render_finite(renderer, camera).astype(float)
        hdr = renderer.read_hdr()
    finally:
        renderer.release()
    daylight = Daylight.at(hours)
    rays = god_ray_uniforms(
        camera.view_projection(SIZE[0] / SIZE[1]), camera.eye, daylight.sun_direction, daylight.sun_color
    )
    added = god_rays_reference(hdr, rays["u_sun_screen"], rays["u_god_rays"])
    off = np.abs(image - tone_map(hdr + added, daylight.exposure)).max(axis=-1)
    without = np.abs(image - tone_map(hdr, daylight.exposure)).max(axis=-1) > 1
    print(
        f"{int((off > 1).sum())} of {off.size} pixels differ from the twin by more than 1/255 (max {off.max():.0f}); "
        f"the rays change {int(without.sum())}"
    )
    Image.fromarray(image.astype(np.uint8)).save(output_dir / "god_rays_park.png")
    assert without.mean() > 0.1, "the view shows rays"
    assert (off > 1).mean() < 0.001 and off.max() <= 3


def test_exposure_follows_the_daylight():
    """The exposure rises from 0.5 by day to 1.3 at night: the tone map lifts the dark scene."""
    noon, night = Daylight.at(13.0), Daylight.at(23.0)
    assert noon.exposure == pytest.approx(0.5, abs=0.05) and night.exposure == pytest.approx(1.3, abs=0.05)
