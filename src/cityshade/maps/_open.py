"""From a map file to what a render needs: the City, the camera to use and the sky's settings."""

from __future__ import annotations

from pathlib import Path

from ..errors import UsageError
from ..scene import City
from ._cameras import parse_camera_spot, spot_camera
from ._scene import map_city
from .features.city_objects import given_ground_height


def city_from_map(
    path: Path | None,
    camera: str = "street",
    date: str | None = None,
    time: str = "19:10",
    city: City | None = None,
    lod: str | None = None,
    terrain: Path | None = None,
) -> tuple[City, str, dict]:
    """(city, camera name, render settings) for `cityshade render/view/video --map FILE`.

    `camera` is a viewpoint name or 'lon,lat,height,heading' (added to the city's viewpoints under
    that text). The settings place the sun and moon over the map at `date` and `time` (local clock
    time). `city`: the map's city made already (a tile cache's); `path` is then not read. `lod`: the
    CityJSON level of detail to draw, `terrain` the DEM under the map (load_map)."""
    from . import load_map
    from ._sun import sky_settings

    spot = parse_camera_spot(camera)
    sky_settings(date, time)  # bad values fail before the map is read
    if city is None:
        city = map_city(load_map(path, lod, terrain))
    if spot is not None:
        city.viewpoints[camera] = spot_camera(city.origin, city.crs, spot, given_ground_height(city))
    elif camera == "street" and "street" not in city.viewpoints:
        camera = "aerial"  # a map without a driven road
    elif camera not in city.viewpoints:
        raise UsageError(
            f"unknown camera {camera!r} for a map; use {', '.join(city.viewpoints)} or lon,lat,height,heading"
        )
    return city, camera, sky_settings(date, time, city.origin)
