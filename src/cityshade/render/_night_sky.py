"""The night: the dusk sky of `assets.sky_colour` giving way, as the sun sinks from civil through
nautical to astronomical twilight, to the night's own sky (with the glow of the town's lights and
the moonlit sky), with the moon's disc (linear HDR, on the environment cube map's texels, for reflections). The stars and
the sun's and moon's discs are drawn per pixel by the sky pass (shaders/frame/stars.glsl,
frame/sky.glsl), finer than a texel."""

from __future__ import annotations

import numpy as np

NIGHT_ZENITH = np.float32([0.0035, 0.0055, 0.014])  # a clear moonless sky away from towns: blue-black
NIGHT_HORIZON = np.float32([0.006, 0.008, 0.016])  # airglow and starlight thicken toward the horizon
# the glow of a town's lights on the air over it (LED and sodium mixed: amber, not red), fading with
# height above the horizon over LIGHT_POLLUTION_HEIGHT (sine of the angle)
LIGHT_POLLUTION = np.float32([0.045, 0.035, 0.02])
LIGHT_POLLUTION_HEIGHT = 0.18
MOONLIT_SKY = np.float32([0.012, 0.02, 0.04])  # the sky a full moon high up scatters: a dim day-blue
MOON_RADIUS = 0.03  # radians: larger than the real moon so it covers a few texels
MOON_RADIANCE = np.float32([2.2, 2.3, 2.5])


def night_amount(sun_elevation: float) -> float:
    """How far the night has replaced the twilight sky: 0 until the end of civil twilight (the sun
    6 degrees below the horizon; a white night never passes it), about 0.5 at the end of nautical
    twilight (12 below), 1 at astronomical night (18 below)."""
    t = float(np.clip((-6.0 - sun_elevation) / 12.0, 0.0, 1.0))
    return t * t * (3 - 2 * t)


def night_dimming(night: float) -> float:
    """What the night leaves of the twilight sky's radiance (the sun's disc too): the glow on the
    sun's side fades faster than the night's own sky rises."""
    return (1.0 - night) ** 2


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
    """Radiance (..., 3) turned toward the night sky by `night` (0..1): blue-black overhead, lighter at
    the horizon, an amber glow of the town's lights low down, and the blue of a moonlit sky when the
    moon (unit vector `moon`, lit fraction `moon_lit`) is up; with `disc`, its disc."""
    dirs = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
    up = np.clip(dirs[..., 1], 0.0, 1.0)[..., None]
    dark = NIGHT_ZENITH + (NIGHT_HORIZON - NIGHT_ZENITH) * (1.0 - up) ** 4
    dark = dark + LIGHT_POLLUTION * np.exp(-up / LIGHT_POLLUTION_HEIGHT)
    if moon is not None:
        dark = dark + MOONLIT_SKY * np.float32(moon_lit * np.clip(moon[1] / 0.5, 0.0, 1.0))
    sky = radiance * np.float32(night_dimming(night)) + dark.astype(np.float32) * np.float32(night)
    if moon is not None and disc:
        sky[(dirs @ np.asarray(moon, np.float32)) > np.cos(MOON_RADIUS)] = moon_radiance(moon_lit)
    dimmed = radiance * np.float32(night_dimming(night)) + np.float32(NIGHT_HORIZON * 0.3 * night)
    return np.where(up > 0.0, sky, dimmed).astype(np.float32)
