"""MapData -> City in stages that each return new data: read and repair (`load_map`, maps/_assemble.py),
guess (`guess_missing`, on a copy), layers (`city_from_guessed`: the buildings' masses and every
feature's layer, maps/features/, with viewpoints framed from the data)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from ..errors import CityshadeError
from ..scene import Camera, City
from ._cameras import FRAMED_SHARE, aerial_camera, framed_area, given_street_camera, street_camera
from ._model import MapData, to_scene
from .features import city_layers

MARGIN = 30.0  # metres of ground kept around the data


def map_city(map_data: MapData) -> City:
    """The city a map describes: its gaps filled (`guess_missing`), then laid out (`city_from_guessed`).
    `map_data` is left as it was read."""
    from ._guess import guess_missing

    return city_from_guessed(guess_missing(map_data))


def city_from_guessed(map_data: MapData) -> City:
    """The buildings (`building_masses`), every feature's layer, and the 'aerial' and 'street' views
    of a map that guessing has filled."""
    from ._masses import building_masses

    masses = building_masses(map_data)
    if not masses:
        raise CityshadeError(f"{map_data.source}: no building to draw", exit_code=2)
    x0, y0, x1, y1 = map_data.bounds()
    (sx0, sz0), (sx1, sz1) = to_scene([(x0, y1), (x1, y0)])  # north (max y) is -z
    bounds = (float(sx0 - MARGIN), float(sz0 - MARGIN), float(sx1 + MARGIN), float(sz1 + MARGIN))
    drawn = [b for b in map_data.buildings if b.drawn]
    # heights as given: a CityJSON city stands where its file says; the tallest 2% left out (a mast)
    heights = np.array([m.height for m in masses]) if masses else np.array([10.0])
    tall = float(np.quantile(heights, FRAMED_SHARE)) if len(heights) >= 50 else float(heights.max())
    framed = framed_area(map_data)
    area = to_scene(np.asarray(framed.exterior.coords)[:-1])
    low, high = _relief_under(map_data, framed)
    viewpoints = {"aerial": aerial_camera(area, tall + high, bottom=low)}
    street = street_camera(map_data, [b.outline for b in drawn]) or given_street_camera(map_data)
    if street is not None:
        viewpoints["street"] = _on_terrain(street, map_data)
    return City(
        map_data.name,
        0,
        masses,
        [],
        bounds,
        viewpoints,
        layers=city_layers(map_data),
        origin=map_data.origin,
        crs=map_data.crs,
    )


def _relief_under(map_data: MapData, area: shapely.Polygon) -> tuple[float, float]:
    """The lowest and highest ground under a map-metre area: the terrain's, else the map's own level."""
    if map_data.terrain is None:
        return map_data.ground_level, map_data.ground_level
    x0, y0, x1, y1 = area.bounds
    x, y = np.meshgrid(np.linspace(x0, x1, 64), np.linspace(y0, y1, 64))
    inside = shapely.contains_xy(area, x, y)
    heights = map_data.terrain.height_at(x[inside], y[inside]) if inside.any() else np.zeros(1)
    return float(heights.min()), float(heights.max())


def _on_terrain(camera: Camera, map_data: MapData) -> Camera:
    """A street-level camera lifted by the terrain's height under its eye (it stays EYE_HEIGHT above it)."""
    if map_data.terrain is None:
        return camera
    lift = float(map_data.terrain.scene_height_at(camera.eye[0], camera.eye[2]))
    up = np.array([0.0, lift, 0.0])
    return replace(camera, position=tuple(camera.eye + up), target=tuple(np.asarray(camera.target) + up))
