"""Viewpoints framed from the map: the whole extract from the air, a real street at eye height,
and any spot given as longitude, latitude, height and heading."""

from __future__ import annotations

import numpy as np
import shapely

from ..errors import UsageError
from ..scene import Camera
from ._model import MapData, to_scene
from .features.streets import MAIN_ROADS

AERIAL_FOV = 50.0
AERIAL_ASPECT = 16 / 9  # the default image size; narrower images see a little less at the sides
AERIAL_PITCH = 45.0  # degrees below the horizon
AERIAL_HEADING = 0.0  # the first heading tried: the camera looks north
STREET_FOV = 66.0
EYE_HEIGHT = 1.7
# where a street camera stands: streets people walk first; other town roads only where a map has none;
# never a motorway, a trunk road or a slip road
STREET_VIEWS = (
    ("residential", "tertiary", "living_street", "pedestrian"),
    tuple(k for k in MAIN_ROADS if k not in ("motorway", "trunk", "residential", "tertiary")),
)
STREET_FACING = 30.0  # metres either side of a street within which its buildings face it
AERIAL_MARGIN = 12.0  # metres of ground the aerial view keeps around the buildings
FRAMED_SHARE = 0.98  # the aerial view frames this share of the buildings: a lone farm far out is left out
STREET_BACK = 25.0  # metres from a building drawn as given that its street view stands
EYE_CLEARANCE = 3.0  # metres from any building that eye keeps
FAR = 1_000_000.0  # the ground reaches the horizon; the depth buffer's precision is set by `near`


def heading_vector(heading: float, pitch: float = 0.0) -> np.ndarray:
    """Scene direction for a compass heading (degrees clockwise from north) and a pitch (degrees up)."""
    h, p = np.radians(heading), np.radians(pitch)
    return np.array([np.sin(h) * np.cos(p), np.sin(p), -np.cos(h) * np.cos(p)])


def _clip(corners: np.ndarray, eye: np.ndarray, forward: np.ndarray, fov: float, aspect: float) -> np.ndarray:
    """Clip coordinates (n, 4) of `corners` seen from `eye` looking along `forward`."""
    camera = Camera(tuple(eye), tuple(eye + forward), fov_y=fov, near=0.5, far=FAR)
    return np.c_[corners, np.ones(len(corners))] @ camera.view_projection(aspect).T


def _fits(clip: np.ndarray) -> bool:
    if np.any(clip[:, 3] <= 0):
        return False
    ndc = clip[:, :2] / clip[:, 3:4]
    return bool(np.all(np.abs(ndc) <= 0.96))


def framed_area(map_data: MapData) -> shapely.Polygon:
    """The ground (map metres) the aerial view frames: the convex hull of the buildings (all but the
    outermost 1 - FRAMED_SHARE of them on each side), AERIAL_MARGIN around it, within the file's
    declared extent when it has one; never the land use, water or roads around them, which may reach
    far out of the extract. Without buildings, the declared extent or the data's bounds."""
    outlines = np.asarray([b.outline for b in map_data.buildings if b.drawn], dtype=object)
    if not len(outlines):
        return shapely.box(*(map_data.declared_bounds or map_data.bounds()))
    boxes = shapely.bounds(outlines)
    cut = (1.0 - FRAMED_SHARE) / 2 if len(outlines) >= 50 else 0.0
    low, high = np.quantile(boxes[:, :2], cut, axis=0), np.quantile(boxes[:, 2:], 1.0 - cut, axis=0)
    kept = outlines[np.all((boxes[:, :2] >= low) & (boxes[:, 2:] <= high), axis=1)]
    # the hull of the outlines together: the hull of their union, without the union's cost
    area = shapely.convex_hull(shapely.geometrycollections(kept if len(kept) else outlines)).buffer(AERIAL_MARGIN, 2)
    if map_data.declared_bounds is not None:
        clipped = area.intersection(shapely.box(*map_data.declared_bounds))
        area = clipped if clipped.area > 0 else area
    return shapely.convex_hull(area)


def aerial_camera(area_points: np.ndarray, top: float, aspect: float = AERIAL_ASPECT, bottom: float = 0.0) -> Camera:
    """Looks down at AERIAL_PITCH on the ground polygon `area_points` ((n, 2) scene x, z) from just far
    enough that it, from height `bottom` (the ground) up to `top`, lies in the frustum; of the headings
    AERIAL_HEADING + k * 45 degrees and of the aim points along each heading, the ones that let it
    stand closest."""
    area_points = np.asarray(area_points, float)
    corners = np.array([(x, y, z) for x, z in area_points for y in (bottom, top)], float)
    x0, z0 = area_points.min(axis=0)
    x1, z1 = area_points.max(axis=0)
    middle = np.array([(x0 + x1) / 2, bottom, (z0 + z1) / 2])
    reach = max(x1 - x0, z1 - z0) / 2
    best = None
    for turn in range(8):
        forward = heading_vector(AERIAL_HEADING + 45.0 * turn, -AERIAL_PITCH)
        ahead = np.array([forward[0], 0.0, forward[2]]) / np.hypot(forward[0], forward[2])
        for shift in np.linspace(-0.4, 0.4, 9) * reach:  # the far side looks smaller: aim past the middle
            centre = middle + ahead * shift
            distance = _fit_distance(corners, centre, forward, aspect)
            if best is None or distance < best[0] - 1e-6:
                best = (distance, forward, centre)
    distance, forward, centre = best
    eye = centre - forward * distance
    # the nearest ground is about half the distance away: a large near plane keeps roads apart from the
    # ground; the shadows reach the far side of the map
    return Camera(
        tuple(eye), tuple(centre), fov_y=AERIAL_FOV, near=max(0.5, distance / 40), far=FAR, shadow_far=2.0 * distance
    )


def _fit_distance(corners: np.ndarray, centre: np.ndarray, forward: np.ndarray, aspect: float) -> float:
    """The smallest distance from `centre` back along `forward` at which every corner is in view
    (bisection). The clip coordinates move linearly with the distance (the view turns with the
    direction only), so two cameras give them at every distance."""
    at_centre = _clip(corners, centre, forward, AERIAL_FOV, aspect)
    per_metre = _clip(corners, centre - forward, forward, AERIAL_FOV, aspect) - at_centre

    def fits(distance):
        return _fits(at_centre + distance * per_metre)

    near, far = 0.0, 1.0
    while not fits(far):
        near, far = far, far * 1.5
    for _ in range(30):
        middle = (near + far) / 2
        near, far = (near, middle) if fits(middle) else (middle, far)
    return far


def street_choice(map_data: MapData, outlines=()):
    """(road, start, end) in map metres of the street a street camera stands on, or None: of the
    segments 25 m or longer on the first STREET_VIEWS tier the map has, the one with the most building
    outlines within STREET_FACING metres, times its length (up to 150 m), discounted by distance from
    the middle of the buildings; its eye point inside none of `outlines`."""
    x0, y0, x1, y1 = framed_area(map_data).bounds
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    radius = max(x1 - x0, y1 - y0, 1.0) / 2
    tree = shapely.STRtree(list(outlines))
    for tier in STREET_VIEWS:
        candidates = []
        for road in map_data.roads:
            if road.kind not in tier or road.tunnel or road.bridge:
                continue
            points = np.asarray(road.line.coords)[:, :2]
            for a, b in zip(points[:-1], points[1:]):
                length = float(np.linalg.norm(b - a))
                if length < 25.0:
                    continue
                facing = len(tree.query(shapely.LineString([a, b]), predicate="dwithin", distance=STREET_FACING))
                distance = float(np.linalg.norm((a + b) / 2 - centre))
                score = min(length, 150.0) * (1 + facing) / (1.0 + (distance / (0.35 * radius)) ** 2)
                candidates.append((score, road, a, b))
        candidates.sort(key=lambda c: -c[0])
        for _, road, a, b in candidates:
            if not len(tree.query(shapely.Point(*_eye_point(a, b)), predicate="intersects")):
                return road, a, b
    return None


def street_segment(map_data: MapData, outlines=()):
    """(start, end) in map metres of `street_choice`'s segment, or None."""
    choice = street_choice(map_data, outlines)
    return None if choice is None else choice[1:]


def _eye_point(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a + 0.1 * (b - a)


def street_camera(map_data: MapData, outlines=()) -> Camera | None:
    """Stands on `street_segment` at eye height, a tenth of the way along, looking along it."""
    segment = street_segment(map_data, outlines)
    if segment is None:
        return None
    a, b = segment
    eye = _eye_point(a, b)
    target = eye + (b - a) / np.linalg.norm(b - a) * 60.0
    (ex, ez), (tx, tz) = to_scene([eye, target])
    return Camera(
        (float(ex), EYE_HEIGHT, float(ez)),
        (float(tx), EYE_HEIGHT + 6.0, float(tz)),
        fov_y=STREET_FOV,
        near=0.3,
        far=FAR,
    )


def parse_camera_spot(text: str) -> tuple[float, float, float, float] | None:
    """'lon,lat,height,heading' -> numbers; None when `text` is a viewpoint name (no comma)."""
    if "," not in text:
        return None
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if (
        len(values) != 4
        or not all(np.isfinite(values))
        or not (-180 <= values[0] <= 180 and -90 <= values[1] <= 90)
        or values[2] < 0
    ):
        raise UsageError(
            f"invalid --camera {text!r}; use lon,lat,height,heading (degrees, degrees, metres above "
            "the ground, degrees clockwise from north), e.g. 24.9449,60.1699,1.7,90"
        )
    return tuple(values)


def spot_camera(origin: tuple[float, float], crs: str, spot: tuple[float, float, float, float], ground=None) -> Camera:
    """A camera at a longitude/latitude `height` metres above the ground, facing `heading`; above
    street level it tilts down so the ground ahead fills the lower half of the picture. `ground`:
    the ground's height at a scene (x, z) where it is not 0 (heights as given: CityJSON)."""
    from pyproj import Transformer

    lon, lat, height, heading = spot
    project = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    east, north = project.transform(lon, lat)
    east0, north0 = project.transform(*origin)
    x, z = to_scene([east - east0, north - north0])
    pitch = -min(45.0, float(np.degrees(np.arctan2(max(height - 20.0, 0.0), 300.0))))
    eye = np.array([x, max(height, 0.3) + (ground(x, z) if ground is not None else 0.0), z])
    return Camera(
        tuple(eye),
        tuple(eye + heading_vector(heading, pitch) * 50.0),
        fov_y=STREET_FOV,
        near=max(0.3, height / 100),
        far=FAR,
    )


def given_street_camera(map_data: MapData) -> Camera | None:
    """For buildings drawn as given (CityJSON, no streets read): at eye height on the ground beside the
    building nearest the map's middle, STREET_BACK metres out from its outline, looking at it, from
    the first of eight directions (away from the middle first) whose eye stands clear of every building."""
    given = [b for b in map_data.buildings if b.drawn and b.surfaces is not None]
    if not given:
        return None
    x0, y0, x1, y1 = map_data.bounds()
    middle = shapely.Point((x0 + x1) / 2, (y0 + y1) / 2)
    building = min(given, key=lambda b: b.outline.distance(middle))
    centre = np.asarray(building.outline.centroid.coords[0])
    away = centre - np.asarray(middle.coords[0])
    start = np.arctan2(away[1], away[0]) if np.linalg.norm(away) > 1.0 else -np.pi / 2  # else from the south
    radius = float(np.sqrt(building.outline.area / np.pi))
    tree = shapely.STRtree([b.outline for b in map_data.buildings if b.drawn])
    eyes = [
        centre + (radius + STREET_BACK) * np.array([np.cos(start + turn), np.sin(start + turn)])
        for turn in np.radians(np.arange(0.0, 360.0, 45.0))
    ]
    clear = [e for e in eyes if not len(tree.query(shapely.Point(e).buffer(EYE_CLEARANCE), predicate="intersects"))]
    eye = (clear or eyes)[0]
    (ex, ez), (tx, tz) = to_scene([eye, centre])
    ground = building.ground
    return Camera(
        (float(ex), ground + EYE_HEIGHT, float(ez)),
        (float(tx), ground + EYE_HEIGHT + 0.35 * (building.height or 10.0), float(tz)),
        fov_y=STREET_FOV,
        near=0.3,
        far=FAR,
    )
