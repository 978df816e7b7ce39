"""Environment radiance for window reflections (paper §2.3): the sky alone, from day to dusk.

No distant skyline is painted in: a city seen in reflections has to come from the scene itself.

Radiance is linear HDR (the sun disc is far above 1). The cube map uses the
OpenGL face order +X, -X, +Y, -Y, +Z, -Z and the standard GL face orientation
(OpenGL 4.5 spec, table 8.19): for texel (row t, column s) with sc = 2(s+0.5)/N-1
and tc = 2(t+0.5)/N-1 the direction is

    +X: ( 1, -tc, -sc)   -X: (-1, -tc,  sc)
    +Y: (sc,   1,  tc)   -Y: (sc,  -1, -tc)
    +Z: (sc, -tc,   1)   -Z: (-sc, -tc, -1)

Row 0 is t = 0, so each face uploads to glTexImage2D as it is.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ._draw import value_noise

DEFAULT_SUN = (-0.55, 0.2, -0.81)
SUN_RADIUS = 0.02  # radians, a little larger than the real sun so it covers texels
SUN_RADIANCE = 20.0


def _mix(a, b, t):
    a = np.asarray(a, np.float32)
    b = np.asarray(b, np.float32)
    return a + (b - a) * np.asarray(t, np.float32)[..., None]


def _normalise(x):
    x = np.asarray(x, np.float32)
    return x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), 1e-12)


def sun_colour(dusk: float) -> np.ndarray:
    """The sun's colour, white by day, orange at dusk (its disc is SUN_RADIANCE times it)."""
    return _mix((1.0, 0.95, 0.88), (1.0, 0.45, 0.16), float(np.clip(dusk, 0.0, 1.0)))


def sky_colour(direction, sun_direction=DEFAULT_SUN, dusk: float = 0.7, disc: bool = True) -> np.ndarray:
    """Linear HDR radiance (..., 3) float32 seen along unit-ish `direction` (..., 3).

    y is up. dusk = 0 is day, 1 late dusk. Below the horizon is dark ground. Without `disc`, the
    sky around the sun but not its disc (the sky pass draws that per pixel, shaders/frame/sky.glsl).
    """
    dirs = _normalise(direction)
    sun = _normalise(sun_direction)
    dusk = float(np.clip(dusk, 0.0, 1.0))
    x, y, z = dirs[..., 0], dirs[..., 1], dirs[..., 2]
    cos_sun = dirs @ sun
    flat = np.hypot(x, z) + 1e-6
    sun_flat = np.hypot(sun[0], sun[2]) + 1e-6
    towards = np.clip(((x * sun[0] + z * sun[2]) / (flat * sun_flat) + 1) * 0.5, 0, 1)

    zenith = _mix((0.10, 0.24, 0.62), (0.025, 0.05, 0.14), dusk)  # twilight's zenith stays blue
    glow_side = _mix((0.2, 0.18, 0.3), (1.5, 0.5, 0.14), towards**3)  # the earth's shadow, pink-grey
    horizon = _mix(np.broadcast_to(np.float32([0.55, 0.68, 0.85]), glow_side.shape), glow_side, dusk)
    up = np.clip(y, 0, 1)
    sky = _mix(horizon, zenith, up**0.45)

    sun = sun_colour(dusk)
    near = np.clip(cos_sun, 0, 1)
    sky += sun * (1.5 * near**200 + 0.35 * near**12)[..., None]

    # Soft clouds on a plane above the viewer, fading out toward the horizon.
    lift = np.maximum(y, 0) + 0.12
    px, pz = x / lift * 2.5, z / lift * 2.5
    cloud = (
        0.55 * value_noise(px, pz, 21)
        + 0.3 * value_noise(px * 2.3, pz * 2.3, 22)
        + 0.15 * value_noise(px * 5, pz * 5, 23)
    )
    cover = np.clip((cloud - 0.5) / 0.2, 0, 1) * np.clip(y / 0.15, 0, 1) * 0.75
    cloud_colour = _mix(
        np.broadcast_to(np.float32([0.95, 0.95, 0.98]), sky.shape),
        _mix((0.16, 0.15, 0.22), (1.1, 0.5, 0.35), towards**2),
        dusk,
    )
    sky = _mix(sky, cloud_colour, cover)

    if disc:
        sky[cos_sun > np.cos(SUN_RADIUS)] = sun * SUN_RADIANCE

    ground = _mix(
        horizon * 0.25, np.broadcast_to(np.float32([0.02, 0.02, 0.025]), horizon.shape), np.clip(-y * 6, 0, 1)
    )
    sky = np.where((y < 0)[..., None], ground, sky)
    return sky.astype(np.float32)


def cube_directions(size: int) -> np.ndarray:
    """(6, size, size, 3) unnormalised directions of texel centres, GL face order and orientation."""
    c = (np.arange(size, dtype=np.float32) + 0.5) / size * 2 - 1
    sc = np.broadcast_to(c[None, :], (size, size))
    tc = np.broadcast_to(c[:, None], (size, size))
    one = np.ones((size, size), np.float32)
    faces = [
        (one, -tc, -sc),
        (-one, -tc, sc),
        (sc, one, tc),
        (sc, -one, -tc),
        (sc, -tc, one),
        (-sc, -tc, -one),
    ]
    return np.stack([np.stack(f, -1) for f in faces])


@lru_cache(maxsize=8)
def _cubemap(size: int, sun: tuple[float, float, float], dusk: float, disc: bool) -> np.ndarray:
    radiance = sky_colour(cube_directions(size), sun, dusk, disc)
    radiance.flags.writeable = False
    return radiance


def environment_cubemap(size: int = 128, sun_direction=DEFAULT_SUN, dusk: float = 0.7, disc: bool = True) -> np.ndarray:
    """(6, size, size, 3) float32 linear HDR radiance of sky_colour on a GL cube map.

    Faces in GL order +X, -X, +Y, -Y, +Z, -Z with the orientation in this module's
    docstring; row 0 of each face is t = 0. Read-only (cached).
    """
    sun = tuple(float(c) for c in np.asarray(sun_direction, np.float64).reshape(3))
    return _cubemap(int(size), sun, float(dusk), bool(disc))
