"""Where each sample's camera stands, where it looks, and when: drawn from the seed and the sample's
index alone (numpy's generator seeded with [seed, index]), so any worker draws the same view.

Street views stand on a street centreline (a map's roads, or the built-in district's streets)
picked by length: pedestrians at the pavement's edge at `pedestrian_height`, vehicles in a lane at
a height from `vehicle_height`, looking along the street or (with probability `across`) across it.
Aerial views look down at `aerial_pitch` onto a street point from `aerial_height`.
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass

import numpy as np
import shapely

from ..maps import MAIN_ROADS, ROAD_LINKS
from ..scene import PATHS, Camera, City
from ._config import DatasetConfig

KINDS = ("pedestrian", "vehicle", "aerial")
STREET_KINDS = MAIN_ROADS + ("living_street", "pedestrian", "service") + ROAD_LINKS + ("road",)
BUILT_IN_STREET_WIDTH = 11.0  # the default city's 16 m streets less the pavements reaching into them
TRIES = 32  # street points tried before a view inside a building is given up


@dataclass(frozen=True)
class Streets:
    """Street centreline segments in scene metres: (N, 2, 2) ends as (x, z), widths (N,), and the
    building outlines (scene x, z) that no street camera may stand in."""

    segments: np.ndarray
    widths: np.ndarray
    blocked: shapely.STRtree | None = None

    @classmethod
    def from_map(cls, map_data) -> "Streets":
        from ..maps import to_scene

        segments, widths = [], []
        for road in map_data.roads:
            if road.kind in STREET_KINDS and not road.tunnel and not road.bridge:
                points = to_scene(np.asarray(road.line.coords)[:, :2])
                segments += list(zip(points[:-1], points[1:]))
                widths += [road.width] * (len(points) - 1)
        outlines = [
            shapely.Polygon(to_scene(np.asarray(b.outline.exterior.coords)[:, :2]))
            for b in map_data.buildings
            if b.drawn
        ]
        return cls(
            np.asarray(segments, float).reshape(-1, 2, 2),
            np.asarray(widths, float),
            shapely.STRtree(outlines) if outlines else None,
        )

    @classmethod
    def from_city(cls, city: City) -> "Streets":
        """The built-in district's street rectangles, each as its long centreline."""
        segments = []
        for x0, z0, x1, z1 in city.streets:
            if x1 - x0 >= z1 - z0:
                segments.append(((x0, (z0 + z1) / 2), (x1, (z0 + z1) / 2)))
            else:
                segments.append((((x0 + x1) / 2, z0), ((x0 + x1) / 2, z1)))
        return cls(np.asarray(segments, float).reshape(-1, 2, 2), np.full(len(segments), BUILT_IN_STREET_WIDTH))

    def inside_building(self, point) -> bool:
        return self.blocked is not None and len(self.blocked.query(shapely.Point(*point), predicate="intersects")) > 0


@dataclass(frozen=True)
class View:
    index: int
    kind: str
    eye: tuple[float, float, float]  # scene metres: x east, y up, z south
    heading: float  # degrees clockwise from north
    pitch: float  # degrees above the horizon
    fov: float  # vertical, degrees
    near: float
    date: str | None  # None for the built-in cities (their sun follows the clock alone)
    hours: float  # local clock time

    def camera(self) -> Camera:
        h, p = np.radians(self.heading), np.radians(self.pitch)
        forward = np.array([np.sin(h) * np.cos(p), np.sin(p), -np.cos(h) * np.cos(p)])
        eye = np.asarray(self.eye)
        return Camera(tuple(eye), tuple(eye + forward * 50.0), fov_y=self.fov, near=self.near, far=1_000_000.0)


def _street_point(rng, streets: Streets):
    """A point on a segment picked by length; returns (point, unit direction, street width)."""
    lengths = np.linalg.norm(streets.segments[:, 1] - streets.segments[:, 0], axis=1)
    k = int(rng.choice(len(lengths), p=lengths / lengths.sum()))
    a, b = streets.segments[k]
    direction = (b - a) / lengths[k]
    return a + rng.uniform(0.0, 1.0) * (b - a), direction, float(streets.widths[k])


def _heading(direction) -> float:
    """Compass heading of a scene (x, z) direction (north is -z)."""
    return float(np.degrees(np.arctan2(direction[0], -direction[1])) % 360.0)


def sample_view(index: int, seed: int, config: DatasetConfig, streets: Streets, has_date: bool) -> View:
    rng = np.random.default_rng([seed, index])
    shares = np.array([config.pedestrian, config.vehicle, config.aerial])
    kind = KINDS[int(rng.choice(3, p=shares / shares.sum()))]
    first, last = config.day_range
    day = first + dt.timedelta(days=int(rng.integers(0, (last - first).days + 1)))
    hours = float(rng.uniform(*config.hours))
    for _ in range(TRIES):
        point, direction, width = _street_point(rng, streets)
        side = rng.choice((-1.0, 1.0))
        normal = np.array([-direction[1], direction[0]]) * side
        if kind == "aerial":
            height = float(rng.uniform(*config.aerial_height))
            pitch = -float(rng.uniform(*config.aerial_pitch))
            heading = float(rng.uniform(0.0, 360.0))
            back = height / np.tan(np.radians(-pitch))
            h = np.radians(heading)
            x, z = point - np.array([np.sin(h), -np.cos(h)]) * back
            eye, near = (float(x), height, float(z)), max(0.5, height / 100.0)
            break
        if kind == "pedestrian":
            x, z = point + normal * (width / 2 + 1.0)
            height, pitch = config.pedestrian_height, float(rng.uniform(-5.0, 12.0))
        else:
            x, z = point + normal * width / 4
            height, pitch = float(rng.uniform(*config.vehicle_height)), float(rng.uniform(-5.0, 8.0))
        look = direction * rng.choice((-1.0, 1.0))
        if rng.uniform() < config.across:
            look = normal
        heading = (_heading(look) + float(rng.uniform(-10.0, 10.0))) % 360.0
        eye, near = (float(x), height, float(z)), 0.3
        if not streets.inside_building((x, z)):
            break
    return View(index, kind, eye, heading, pitch, config.fov, near, day.isoformat() if has_date else None, hours)


SEQUENCES = ("walk", "orbit")  # --path
WALK_STEP = 2.0  # metres at most between consecutive walk views, so that neighbours overlap


def _key(point) -> tuple[float, float]:
    return (round(float(point[0]), 3), round(float(point[1]), 3))


def walk_route(streets: Streets) -> np.ndarray:
    """(M, 2) points of a walk: from one end of the longest segment, at each junction on along the
    straightest street not walked yet, until none is left."""
    segments = streets.segments
    ends: dict[tuple, list[tuple[int, int]]] = {}
    for k, (a, b) in enumerate(segments):
        ends.setdefault(_key(a), []).append((k, 1))
        ends.setdefault(_key(b), []).append((k, 0))
    lengths = np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1)
    current = int(np.argmax(lengths))
    used = {current}
    route = [segments[current][0], segments[current][1]]
    while True:
        heading = (route[-1] - route[-2]) / max(np.linalg.norm(route[-1] - route[-2]), 1e-9)
        options = []
        for k, far in ends.get(_key(route[-1]), []):
            if k in used or lengths[k] <= 0:
                continue
            step = (segments[k][far] - route[-1]) / lengths[k]
            options.append((float(step @ heading), k, far))
        if not options:
            return np.asarray(route)
        _, k, far = max(options)
        used.add(k)
        route.append(segments[k][far])


def _along(route: np.ndarray, distance: float):
    """(point, unit direction) at `distance` metres along a polyline."""
    steps = np.linalg.norm(np.diff(route, axis=0), axis=1)
    at = np.concatenate([[0.0], np.cumsum(steps)])
    k = int(np.clip(np.searchsorted(at, distance, side="right") - 1, 0, len(steps) - 1))
    direction = (route[k + 1] - route[k]) / max(steps[k], 1e-9)
    return route[k] + direction * (distance - at[k]), direction


def walk_eye(streets: Streets, route: np.ndarray, distance: float, height: float):
    """(eye, heading) `distance` metres along the walk route: on the right-hand pavement (half the
    streets' median width and a metre off the centreline), looking along the street."""
    point, direction = _along(route, distance)
    width = float(np.median(streets.widths))
    x, z = point + np.array([-direction[1], direction[0]]) * (width / 2 + 1.0)
    return (float(x), height, float(z)), _heading(direction)


def route_length(route: np.ndarray) -> float:
    return float(np.sum(np.linalg.norm(np.diff(route, axis=0), axis=1)))


def walk_camera(streets: Streets, t: float, height: float = 1.7, fov: float = 60.0) -> Camera:
    """The camera a share `t` (0..1) of the way along the whole walk route (cityshade video --path walk)."""
    route = walk_route(streets)
    eye, heading = walk_eye(streets, route, t * route_length(route), height)
    return View(0, "walk", eye, heading, 0.0, fov, 0.3, None, 12.0).camera()


def sequence_view(
    index: int,
    frames: int,
    path: str,
    seed: int,
    config: DatasetConfig,
    streets: Streets,
    has_date: bool,
    city: City | None = None,
) -> View:
    """View `index` of `frames` consecutive views: `walk` at pedestrian height beside the walk
    route's carriageway, looking ahead, WALK_STEP metres apart at most; `orbit` once around the
    city's buildings as `cityshade video` circles them (scene's orbit path, `city` needed).
    Every frame has the same date and time (from the seed)."""
    rng = np.random.default_rng([seed])
    first, last = config.day_range
    day = first + dt.timedelta(days=int(rng.integers(0, (last - first).days + 1)))
    hours = float(rng.uniform(*config.hours))
    date = day.isoformat() if has_date else None
    if path == "walk":
        route = walk_route(streets)
        step = min(route_length(route) / max(frames - 1, 1), WALK_STEP)
        eye, heading = walk_eye(streets, route, index * step, config.pedestrian_height)
        return View(index, "walk", eye, heading, 0.0, config.fov, 0.3, date, hours)
    camera = PATHS["orbit"](city, index / frames)
    look = np.subtract(camera.target, camera.eye)
    heading = _heading(look[[0, 2]])
    pitch = float(np.degrees(np.arctan2(look[1], np.hypot(look[0], look[2]))))
    eye = tuple(float(v) for v in camera.eye)
    return View(index, "orbit", eye, heading, pitch, config.fov, camera.near, date, hours)
