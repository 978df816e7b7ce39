"""Camera paths for videos: a fly-over orbit, a street-level walk, and a fixed view at dusk."""

from __future__ import annotations

import numpy as np

from ..errors import UsageError
from ._camera import Camera
from ._city import City


def orbit(city: City, t: float) -> Camera:
    """Once around the district at rooftop height, looking at its centre."""
    x0, z0, x1, z1 = city.bounds
    centre = np.array([(x0 + x1) / 2, 0.0, (z0 + z1) / 2])
    radius = 0.75 * max(x1 - x0, z1 - z0)
    angle = 2 * np.pi * t
    eye = centre + np.array([radius * np.cos(angle), 0.35 * radius, radius * np.sin(angle)])
    # far enough for a map's ground to reach the horizon; the near plane grows with the distance
    return Camera(
        tuple(eye), tuple(centre + np.array([0.0, 20.0, 0.0])), fov_y=55.0, near=max(0.5, radius / 40), far=1_000_000.0
    )


def walk(city: City, t: float) -> Camera:
    """Eye height, 60 m down the street the 'street' viewpoint stands in (along the street axis
    nearest its heading), keeping its view direction."""
    start = city.camera("street")
    view = np.asarray(start.target, float) - start.eye
    axis = 0 if abs(view[0]) > abs(view[2]) else 2
    ahead = np.zeros(3)
    ahead[axis] = np.sign(view[axis])
    eye = start.eye + ahead * 60.0 * t
    return Camera(tuple(eye), tuple(eye + view), fov_y=start.fov_y, near=start.near, far=start.far)


def still(city: City, t: float) -> Camera:
    """The 'street' viewpoint, unmoving (for time-of-day videos)."""
    return city.camera("street")


PATHS = {"orbit": orbit, "walk": walk, "still": still}


def camera_path(name: str):
    if name not in PATHS:
        raise UsageError(f"unknown camera path {name!r}; allowed: {', '.join(PATHS)}")
    return PATHS[name]
