"""The night: the dusk sky of `assets.sky_colour` darkened as the sun sinks through twilight, with
the moon's disc (linear HDR, on the environment cube map's texels, for reflections). The stars and
the sun's and moon's discs are drawn per pixel by the sky pass (shaders/frame/stars.glsl,
frame/sky.glsl), finer than a texel."""

from __future__ import annotations

import numpy as np

NIGHT_ZENITH = np.float32([0.002, 0.003, 0.008])
MOON_RADIUS = 0.03  # radians: larger than the real moon so it covers a few texels
MOON_RADIANCE = np.float32([2.2, 2.3, 2.5])


def night_amount(sun_elevation: float) -> float:
    """0 until the sun is 4 degrees below the horizon, 1 from 14 degrees below (astronomical night)."""
    t = float(np.clip((-4.0 - sun_elevation) / 10.0, 0.0, 1.0))
    return t * t * (3 - 2 * t)


def night_dimming(night: float) -> float:
    """What the night leaves of the day sky's radiance (the sun's disc too)."""
    return 1.0 - 0.97 * night


def moon_radiance(moon_lit: float) -> np.ndarray:
    return MOON_RADIANCE * np.float32(0.15 + 0.85 * moon_lit)


def night_sky(
    radiance: np.ndarray,
    directions: np.ndarray,
    night: float,
    moon: np.ndarray | None = None,
    moon_lit: float = 1.0,
    disc: bool = True,
) -> np.ndarray:
    """Radiance (..., 3) darkened toward the night sky by `night` (0..1), with the moon's disc toward
    unit vector `moon` (lit fraction `moon_lit`; without `disc`, none: the sky pass draws it per pixel)."""
    dirs = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
    up = np.clip(dirs[..., 1], 0.0, 1.0)[..., None]
    dimmed = radiance * np.float32(night_dimming(night))
    sky = dimmed + NIGHT_ZENITH * np.float32(night)
    if moon is not None and disc:
        sky[(dirs @ np.asarray(moon, np.float32)) > np.cos(MOON_RADIUS)] = moon_radiance(moon_lit)
    return np.where(up > 0.0, sky, dimmed).astype(np.float32)
