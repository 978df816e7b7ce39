"""Time of day -> sun and sky. (The share of lit rooms at each hour, per building use, is
cityshade.scene.lit_shares.)"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SUNRISE, SUNSET = 6.0, 19.0
MAX_ELEVATION = 62.0


def _smoothstep(a: float, b: float, x: float) -> float:
    t = float(np.clip((x - a) / (b - a), 0.0, 1.0))
    return t * t * (3 - 2 * t)


def compass_direction(elevation: float, azimuth: float) -> np.ndarray:
    """Unit scene vector toward a body at `elevation` degrees up and `azimuth` degrees clockwise from
    north (north is -z, east is +x)."""
    el, az = np.radians(elevation), np.radians(azimuth)
    return np.array([np.sin(az) * np.cos(el), np.sin(el), -np.cos(az) * np.cos(el)])


def _clock_sun(hours: float) -> tuple[float, np.ndarray]:
    """A sun that rises at SUNRISE in the east and sets at SUNSET in the west, for the built-in cities."""
    day_phase = (hours - SUNRISE) / (SUNSET - SUNRISE)
    if 0 <= day_phase <= 1:
        elevation = MAX_ELEVATION * np.sin(np.pi * day_phase)
    else:  # the sun sinks about 6 degrees an hour below the horizon
        hours_dark = min((hours - SUNSET) % 24, (SUNRISE - hours) % 24)
        elevation = max(-6.0 * hours_dark, -30.0)
    azimuth = np.pi * np.clip(day_phase, -0.1, 1.1)  # east (+x) through south (+z) to west (-x)
    el = np.radians(elevation)
    sun = np.array([np.cos(azimuth) * np.cos(el), np.sin(el), np.sin(azimuth) * np.cos(el)])
    return float(elevation), sun / np.linalg.norm(sun)


# the light of the sky with the sun below the horizon, by its elevation (degrees): bright through civil
# twilight (down to -6: a white night at 60 N in midsummer never leaves it), fading through nautical
# (-12) and astronomical (-18) twilight to the night's; the exposure opens to keep a twilight readable
TWILIGHT_SKY = ((-18.0, -12.0, -6.0, 0.0), (0.6, 0.75, 1.3, 2.0))
TWILIGHT_EXPOSURE = ((-18.0, -12.0, -6.0, 0.0), (0.8, 1.0, 1.5, 1.5))
MOONLIGHT = np.array([0.55, 0.65, 0.9]) * 0.08  # full moon radiance in the units of sun_color


@dataclass(frozen=True)
class Daylight:
    hours: float
    sun_direction: np.ndarray  # unit vector toward the light that casts shadows (the moon at night)
    sun_color: np.ndarray
    sky_ambient: np.ndarray
    ground_ambient: np.ndarray
    dusk: float  # 0 = day, 1 = night
    exposure: float
    sky_sun: np.ndarray | None = None  # toward the sun itself, for the sky (None: sun_direction)
    moon_direction: np.ndarray | None = None  # toward the moon when it is up and the sun is down
    street_lights: float = 0.0  # 1 when the street lamps are on: the sun is below the horizon
    moon_lit: float = 0.0  # lit fraction of the moon's disc
    sun_elevation: float = 0.0  # degrees

    @classmethod
    def at(
        cls, hours: float, sun: tuple[float, float] | None = None, moon: tuple[float, float, float] | None = None
    ) -> "Daylight":
        """The light at clock time `hours`; `sun` = (elevation, azimuth) in degrees places the sun
        (otherwise a clock sun), `moon` = (elevation, azimuth, lit fraction) lights the night."""
        if sun is None:
            elevation, direction = _clock_sun(hours)
        else:
            elevation, direction = float(sun[0]), compass_direction(*sun)
        high = _smoothstep(0.0, 30.0, elevation)
        above = _smoothstep(-3.0, 1.0, elevation)
        sun_color = above * ((1 - high) * np.array([1.0, 0.5, 0.22]) * 2.2 + high * np.array([1.0, 0.95, 0.86]) * 3.2)
        dusk = 1.0 - _smoothstep(-8.0, 25.0, elevation)
        twilight = float(np.interp(elevation, *TWILIGHT_SKY))
        sky = (1 - dusk) * np.array([0.35, 0.45, 0.6]) + dusk * twilight * np.array([0.05, 0.06, 0.11])
        ground = sky * np.array([0.45, 0.4, 0.35])
        exposure = 0.5 + dusk * float(np.interp(elevation, *TWILIGHT_EXPOSURE))
        if sun is not None:  # maps are mostly seen from above: pale roofs face a high sun squarely
            exposure -= 0.15 * high
        light, moon_direction = direction, None
        if moon is not None and elevation < -3.0 and moon[0] > 0.0:
            moon_direction = compass_direction(moon[0], moon[1])
            light = moon_direction
            sun_color = MOONLIGHT * moon[2] * _smoothstep(0.0, 10.0, moon[0])
        return cls(
            hours,
            light,
            sun_color,
            sky,
            ground,
            float(dusk),
            float(exposure),
            sky_sun=direction,
            moon_direction=moon_direction,
            street_lights=1.0 - _smoothstep(-2.0, 1.0, elevation),
            moon_lit=float(moon[2]) if moon is not None else 0.0,
            sun_elevation=elevation,
        )
