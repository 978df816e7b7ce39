"""What roof a map building has: its shape, height and direction from the Simple 3D Buildings tags,
in the object space of the building's mass (turned so +x runs along the outline's longest side)."""

from __future__ import annotations

import math

import shapely

from ..scene import ROOF_SHAPE_TABLE, Roof
from ._defaults import DEFAULT_ROOF_ANGLE, defaults_for
from ._model import ROOF_SHAPES, MapBuilding

MIN_WALL = 0.5  # metres of wall a roof always leaves under itself (a building that is all roof has none)
# Flat roofs of blocks (PARAPET_LEVELS storeys or more) end in a parapet this high; houses and sheds not.
PARAPET = 0.5
PARAPET_LEVELS = 3
# Dormers: where the map says so (`roof:levels` tagged on a pitched roof, or `roof:dormers` yes or a
# count), else by rule: of the residential buildings (DORMER_KINDS) whose guessed roof has a storey of
# rooms and whose eaves run DORMER_EAVES metres or more, one in DORMER_SHARE (by the building's index:
# neighbours differ, reruns agree); never on other buildings whose map is silent. The share is typical
# of older northern European town houses; a guessed attic without dormers is lit by its gables.
DORMER_KINDS = ("house", "detached", "semidetached_house", "terrace", "apartments", "residential")
DORMER_EAVES = 10.0
DORMER_SHARE = 0.3


def _direction(building: MapBuilding, yaw: float) -> float:
    """The direction (object space, radians from +x toward +z) the main roof face looks, downhill.

    A tagged `roof:direction` means that (as in OpenStreetMap's Simple 3D Buildings: a gabled
    roof's ridge runs across it, a skillion falls toward it). A guessed one only restates the
    orientation it was guessed from, so the orientation decides."""
    if building.roof_direction is not None and "roof_direction" not in building.guessed:
        compass = math.radians(building.roof_direction)
        wx, wz = math.sin(compass), -math.cos(compass)  # east is +x, north is -z
        c, s = math.cos(yaw), math.sin(yaw)
        return math.atan2(s * wx + c * wz, c * wx - s * wz)
    # the ridge runs along the longest side (+x) unless the map says across
    return 0.0 if building.roof_orientation == "across" else math.pi / 2


def has_dormers(building: MapBuilding, outline: shapely.Polygon) -> bool:
    """Whether `building`'s roof with rooms in it carries dormers (the rule above)."""
    said = building.tags.get("roof:dormers", "").strip().lower()
    if said:
        return said not in ("no", "0", "none")
    if "roof_levels" not in building.guessed:
        return True
    x0, _, x1, _ = outline.bounds  # object space: +x runs along the outline's longest side
    if building.kind not in DORMER_KINDS or x1 - x0 < DORMER_EAVES:
        return False
    return (building.index * 2654435761 % 2**32) / 2**32 < DORMER_SHARE


def building_roof(building: MapBuilding, outline: shapely.Polygon, yaw: float, height: float, storey: float) -> Roof:
    """The roof of `building` over its object-space `outline`, turned by `yaw`, on a mass `height`
    metres tall from its base (the roof takes at most what leaves `MIN_WALL` of wall) whose
    storeys are `storey` metres high (the rooms in the roof, where roof:levels says there are)."""
    shape = building.roof_shape if building.roof_shape in ROOF_SHAPES else "flat"
    block = building.has_walls and not building.small_utility and (building.levels or 0) >= PARAPET_LEVELS
    flat = Roof(
        colour=building.roof_colour,
        material=building.roof_material,
        parapet=PARAPET if block and height >= PARAPET + MIN_WALL else 0.0,
        seed=building.index,
    )
    if shape == "flat":
        return flat
    direction = _direction(building, yaw)
    kind = ROOF_SHAPE_TABLE[shape]
    run = kind.run(outline, direction)
    if building.roof_height is not None:
        rise = building.roof_height
    elif building.roof_levels is not None:
        rise = building.roof_levels * defaults_for(building.kind).storey
    elif building.roof_angle is not None:
        rise = math.tan(math.radians(min(building.roof_angle, 89.0))) * run
    else:
        rise = kind.default_rise(run, DEFAULT_ROOF_ANGLE)
    rise = min(rise, height - (MIN_WALL if building.has_walls else 0.0))
    if rise <= 0:
        return flat
    rooms = building.has_walls and (building.roof_levels or 0.0) >= 1.0
    return Roof(
        shape,
        float(rise),
        direction,
        building.roof_colour,
        building.roof_material,
        seed=building.index,
        attic_storey=storey if rooms else 0.0,
        dormers=rooms and has_dormers(building, outline),
    )
