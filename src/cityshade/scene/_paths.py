"""Camera paths for videos: a fly-over orbit, a street-level walk, and a fixed view at dusk."""

from __future__ import annotations

import numpy as np

from ..errors import UsageError
from ._camera import Camera
from ._city import City

ORBIT_REACH = 0.8  # the orbit's ellipse, in half-extents of the buildings: it passes over the outer ones


def _buildings_extent(city: City) -> tuple[np.ndarray, np.ndarray]:
    """(centre, half-size) in scene (x, z) of the buildings' positions (2nd to 98th percentile, so
    that a lone outlier does not stretch it); the city's bounds without buildings."""
    points = city.masses.column("position") if len(city.masses) else np.zeros((0, 2))
    if len(points) == 0:
        x0, z0, x1, z1 = city.bounds
        low, high = np.array([x0, z0]), np.array([x1, z1])
    else:
        low, high = np.percentile(points, 2, axis=0), np.percentile(points, 98, axis=0)
    return (low + high) / 2, np.maximum((high - low) / 2, 20.0)


def orbit(city: City, t: float) -> Camera:
    """Once around the buildings (t from 0 to 1; 1 is back at the start) on an ellipse of
    ORBIT_REACH of their extent, over the outer buildings and half again as high as the tallest,
    looking down at their centre."""
    centre, half = _buildings_extent(city)
    angle = 2 * np.pi * t
    x, z = centre + ORBIT_REACH * half * np.array([np.cos(angle), np.sin(angle)])
    tall = float(np.percentile(city.masses.column("height"), 98)) if len(city.masses) else 0.0
    height = max(0.45 * ORBIT_REACH * float(half.max()), 1.5 * tall)  # above the towers it passes
    eye = np.array([x, height, z])
    # far enough for a map's ground to reach the horizon; the near plane grows with the distance
    return Camera(tuple(eye), (centre[0], 0.0, centre[1]), fov_y=55.0, near=max(0.5, height / 60), far=1_000_000.0)


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
LOOPS = ("orbit",)  # paths whose end is their start: a video's frames stop one step short of it


def camera_path(name: str):
    if name not in PATHS:
        raise UsageError(f"unknown camera path {name!r}; allowed: {', '.join(PATHS)}")
    return PATHS[name]
