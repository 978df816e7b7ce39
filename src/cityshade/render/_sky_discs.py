"""The sun's and the moon's discs, drawn per pixel by the sky pass (shaders/frame/sky.glsl) with an
antialiased edge, over a sky cube map without them: a disc baked into the cube map's texels (as the
reflections still see it) shows their squares when looked at. `sky_discs_reference` is the numpy twin."""

from __future__ import annotations

import numpy as np

from .. import assets
from ..frame import Daylight
from ._night_sky import MOON_RADIUS, moon_radiance, night_amount, night_dimming

DISCS = 2  # the sun, the moon (SKY_DISCS)


def sky_disc_uniforms(daylight: Daylight, rows: int, fov_y_degrees: float) -> dict:
    """u_discs (per disc: unit direction, angular radius), u_disc_radiance (linear HDR; zero for a
    disc not in the sky) and u_pixel_angle (radians a pixel spans at the image's centre)."""
    discs = np.zeros((DISCS, 4), np.float32)
    radiance = np.zeros((DISCS, 3), np.float32)
    discs[0] = (*daylight.sky_sun, assets.SUN_RADIUS)
    radiance[0] = (
        assets.sun_colour(daylight.dusk) * assets.SUN_RADIANCE * night_dimming(night_amount(daylight.sun_elevation))
    )
    if daylight.moon_direction is not None:
        discs[1] = (*daylight.moon_direction, MOON_RADIUS)
        radiance[1] = moon_radiance(daylight.moon_lit)
    pixel = 2.0 * np.tan(np.radians(fov_y_degrees) / 2.0) / rows
    rows_of = lambda a: [tuple(map(float, row)) for row in a]  # noqa: E731 (a uniform array's values)
    return dict(u_discs=rows_of(discs), u_disc_radiance=rows_of(radiance), u_pixel_angle=float(pixel))


def sky_discs_reference(sky: np.ndarray, directions: np.ndarray, uniforms: dict) -> np.ndarray:
    """numpy twin of the sky pass's discs over `sky` (..., 3) seen along unit `directions` (..., 3)."""
    out = sky.astype(np.float64)
    up = directions[..., 1] >= 0.0
    for disc, radiance in zip(np.asarray(uniforms["u_discs"]), np.asarray(uniforms["u_disc_radiance"])):
        angle = np.arccos(np.clip(directions @ disc[:3], -1.0, 1.0))
        cover = np.clip((disc[3] - angle) / uniforms["u_pixel_angle"] + 0.5, 0.0, 1.0) * up
        out += cover[..., None] * (radiance - out)
    return out
