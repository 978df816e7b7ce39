"""The sun and moon over a map at a date and clock time, from astral's solar and lunar positions.

The clock time is the map's standard time: UTC plus its longitude in whole hours (15 degrees an
hour, no daylight saving), so noon is near the sun's highest point anywhere.
"""

from __future__ import annotations

import datetime as dt
import re

from .._values import parse_time
from ..errors import UsageError

DEFAULT_DATE = "2025-06-21"  # the longest day: long low sun in the evening in northern cities


def parse_date(text: str) -> dt.date:
    match = re.fullmatch(r"(\d{4})-(\d{2})-(\d{2})", text.strip())
    try:
        if match is None:
            raise ValueError
        return dt.date(*(int(g) for g in match.groups()))
    except ValueError:
        raise UsageError(f"invalid --date {text!r}; use YYYY-MM-DD, e.g. 2025-06-21") from None


def require_map_for_date(date: str | None, map_path) -> None:
    """--date places the sun over a map's longitude and latitude: without --map it has nothing to do."""
    if date is not None and map_path is None:
        raise UsageError(
            f"--date {date} needs --map FILE: the date places the sun over the map's place; "
            "for the built-in cities use --time alone"
        )


def utc_time(origin: tuple[float, float], date: dt.date, hours: float) -> dt.datetime:
    """The UTC instant of clock time `hours` on `date` at the map's longitude."""
    offset = round(origin[0] / 15.0)
    local = dt.datetime.combine(date, dt.time()) + dt.timedelta(hours=hours)
    return (local - dt.timedelta(hours=offset)).replace(tzinfo=dt.timezone.utc)


def sun_and_moon(origin: tuple[float, float], when: dt.datetime) -> dict:
    """{'sun': (elevation, azimuth), 'moon': (elevation, azimuth, phase 0..1 lit)} in degrees,
    azimuth clockwise from north."""
    import math

    from astral import Observer, moon, sun

    observer = Observer(latitude=origin[1], longitude=origin[0])
    sun_position = (float(sun.elevation(observer, when)), float(sun.azimuth(observer, when)))
    moon_position = (float(moon.elevation(observer, when)), float(moon.azimuth(observer, when)))
    age = moon.phase(when.date()) / 29.53  # 0 new, 0.5 full
    lit = 0.5 * (1.0 - math.cos(2.0 * math.pi * age))
    return {"sun": sun_position, "moon": (*moon_position, lit)}


def sky_clock(origin: tuple[float, float], date: str | None = None):
    """hours -> render settings of the sun and moon over `origin` at that clock time on `date`."""
    day = parse_date(date or DEFAULT_DATE)
    return lambda hours: sun_and_moon(origin, utc_time(origin, day, hours))


def sky_settings(date: str | None, time: str, origin: tuple[float, float] | None = None) -> dict:
    """Render settings for the sun and moon over `origin` (longitude, latitude); {} without an origin.
    Bad dates and times fail here, before anything is loaded."""
    parse_date(date or DEFAULT_DATE)
    hours = parse_time(time)
    return {} if origin is None else sky_clock(origin, date)(hours)
