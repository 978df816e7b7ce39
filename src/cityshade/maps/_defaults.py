"""Regional defaults for what a map leaves out, and the rules that settle contradictory tags.

The numbers describe Finnish (Nordic) towns, the extracts cityshade ships with: a residential storey
is about 3 m floor to floor, a shop or office storey 3.5-4 m; detached houses are one storey with an
attic under a pitched roof ("1½ storeys"), blocks of flats five; sheds, saunas and garages are one
low storey of wood. docs/guesses.md prints the table. The learned model (`_guess.py`) starts from
these and moves toward what the tagged buildings of the same map say.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._model import MapBuilding, ReadReport


@dataclass(frozen=True)
class TypeDefaults:
    levels: float  # storeys below the roof
    storey: float  # metres floor to floor
    roof_shape: str
    material: str
    roof_material: str
    small: bool = False  # a shed-like building: one storey, no rooms, a door and few windows


RESIDENTIAL = TypeDefaults(5, 3.0, "flat", "plaster", "roofing_felt")
HOUSE = TypeDefaults(1, 3.0, "gabled", "wood", "metal")
SMALL_WOOD = TypeDefaults(1, 2.6, "gabled", "wood", "metal", small=True)
SMALL_FLAT = TypeDefaults(1, 2.8, "flat", "wood", "roofing_felt", small=True)
SMALL_METAL = TypeDefaults(1, 8.0, "flat", "metal", "metal", small=True)  # silos, tanks: one tall hollow volume

# building=* value -> defaults. Anything missing here is `yes` (an unknown building).
DEFAULTS: dict[str, TypeDefaults] = {
    "yes": TypeDefaults(3, 3.2, "flat", "plaster", "roofing_felt"),
    "apartments": RESIDENTIAL,
    "residential": RESIDENTIAL,
    "dormitory": RESIDENTIAL,
    "terrace": TypeDefaults(2, 3.0, "gabled", "wood", "metal"),
    "house": HOUSE,
    "detached": HOUSE,
    "semidetached_house": HOUSE,
    "bungalow": HOUSE,
    "farm": HOUSE,
    "cabin": SMALL_WOOD,
    "hut": SMALL_WOOD,
    "sauna": SMALL_WOOD,
    "shed": SMALL_WOOD,
    "toilets": SMALL_WOOD,
    "boathouse": SMALL_WOOD,
    "barn": TypeDefaults(1, 5.0, "gabled", "wood", "metal"),
    "greenhouse": TypeDefaults(1, 2.8, "gabled", "glass", "glass", small=True),
    "garage": SMALL_FLAT,
    "garages": SMALL_FLAT,
    "carport": SMALL_FLAT,
    "kiosk": SMALL_FLAT,
    "shelter": SMALL_FLAT,
    "service": SMALL_FLAT,
    "transformer_tower": SMALL_FLAT,
    "bunker": SMALL_FLAT,
    "silo": SMALL_METAL,
    "storage_tank": SMALL_METAL,
    "tank": SMALL_METAL,
    "roof": TypeDefaults(1, 4.0, "flat", "concrete", "metal"),
    "commercial": TypeDefaults(4, 3.5, "flat", "plaster", "roofing_felt"),
    "retail": TypeDefaults(2, 4.0, "flat", "brick", "roofing_felt"),
    "supermarket": TypeDefaults(1, 5.0, "flat", "concrete", "roofing_felt"),
    "office": TypeDefaults(6, 3.5, "flat", "glass", "roofing_felt"),
    "hotel": TypeDefaults(6, 3.2, "flat", "plaster", "roofing_felt"),
    "industrial": TypeDefaults(2, 4.5, "flat", "concrete", "metal"),
    "warehouse": TypeDefaults(1, 7.0, "flat", "metal", "metal"),
    "school": TypeDefaults(3, 3.5, "flat", "brick", "roofing_felt"),
    "kindergarten": TypeDefaults(1, 3.5, "gabled", "wood", "metal"),
    "university": TypeDefaults(4, 3.8, "flat", "brick", "roofing_felt"),
    "college": TypeDefaults(4, 3.8, "flat", "brick", "roofing_felt"),
    "hospital": TypeDefaults(6, 3.6, "flat", "concrete", "roofing_felt"),
    "public": TypeDefaults(4, 3.6, "flat", "stone", "metal"),
    "civic": TypeDefaults(4, 3.6, "flat", "stone", "metal"),
    "government": TypeDefaults(4, 3.6, "flat", "stone", "metal"),
    "church": TypeDefaults(2, 6.0, "gabled", "brick", "metal"),
    "cathedral": TypeDefaults(3, 8.0, "gabled", "stone", "metal"),
    "chapel": TypeDefaults(1, 5.0, "gabled", "wood", "metal"),
    "train_station": TypeDefaults(2, 5.0, "gabled", "stone", "metal"),
    "transportation": TypeDefaults(1, 5.0, "flat", "concrete", "metal"),
    "stadium": TypeDefaults(2, 7.0, "flat", "concrete", "metal"),
    "sports_hall": TypeDefaults(1, 8.0, "flat", "metal", "metal"),
    "parking": TypeDefaults(4, 3.0, "flat", "concrete", "concrete"),
}

SMALL_FOOTPRINT = 30.0  # m²: below this any building is a shed-like one-storey volume
DEFAULT_ROOF_ANGLE = 30.0  # degrees, a sheet-metal gable
# Kinds whose storeys are legitimately tall (halls, naves, tanks): levels and height never contradict there.
TALL_STOREYS = {
    "church",
    "cathedral",
    "chapel",
    "stadium",
    "sports_hall",
    "warehouse",
    "silo",
    "storage_tank",
    "tank",
    "hangar",
    "industrial",
    "train_station",
    "transportation",
    "barn",
    "tower",
    "water_tower",
}
STOREY_RANGE = (2.2, 6.0)  # metres per storey outside which tagged levels and height disagree
MAX_LEVELS = 165  # more than the tallest building on Earth: a typing error

# Materials -> sRGB colours a guessed material is painted in (Nordic: falu red wood, light plaster).
MATERIAL_COLOURS = {
    "wood": ((0.52, 0.15, 0.11), (0.85, 0.78, 0.55), (0.92, 0.9, 0.84)),
    "plaster": ((0.9, 0.84, 0.68), (0.86, 0.86, 0.82), (0.82, 0.7, 0.55), (0.75, 0.8, 0.78)),
    "brick": ((0.6, 0.27, 0.2), (0.55, 0.32, 0.25)),
    "stone": ((0.72, 0.7, 0.66),),
    "concrete": ((0.66, 0.66, 0.64),),
    "glass": ((0.45, 0.55, 0.6),),
    "metal": ((0.55, 0.57, 0.6), (0.25, 0.27, 0.3)),
    "roofing_felt": ((0.22, 0.22, 0.23),),
}


# building=yes and building=residential say nothing of the size; the footprint does. In Finnish towns an
# untyped footprint under 60 m² is an outbuilding (sauna, storehouse, garage), one under 220 m² a house.
GENERIC = {"yes", "residential"}
OUTBUILDING = TypeDefaults(1, 2.8, "gabled", "wood", "metal")
HOUSE_FOOTPRINT = (60.0, 220.0)


def defaults_for(kind: str, area: float | None = None, is_part: bool = False) -> TypeDefaults:
    """The defaults of a building type; for untyped buildings (and not parts) by footprint area too."""
    if kind in GENERIC and area is not None and not is_part:
        if area < HOUSE_FOOTPRINT[0]:
            return OUTBUILDING
        if area < HOUSE_FOOTPRINT[1]:
            return HOUSE
    return DEFAULTS.get(kind, DEFAULTS["yes"])


def _reject(building: MapBuilding, name: str, report: ReadReport, why: str):
    """Drops a tagged value a rule rejects, so the guess replaces it, and counts why."""
    setattr(building, name, None)
    building.tagged.discard(name)
    report.repair("building", why, building.source_id)


def _retag(building: MapBuilding, name: str, value: float, report: ReadReport, why: str):
    """Replaces a tagged value by the one a rule derives; the new value counts as guessed."""
    setattr(building, name, value)
    building.tagged.discard(name)
    building.guessed.add(name)
    report.repair("building", why, building.source_id)


def _tag(building: MapBuilding, name: str):
    """The value the data gave, or None: the rules judge tags, never earlier guesses."""
    return getattr(building, name) if name in building.tagged else None


def settle_top(building: MapBuilding, report: ReadReport):
    """A top not above the bottom is almost always measured from the bottom (a part's own size)."""
    height = _tag(building, "height")
    if height is not None and building.min_height is not None and height <= building.min_height:
        _retag(
            building,
            "height",
            building.min_height + height,
            report,
            "height not above min_height: read as measured from min_height",
        )


def resolve_contradictions(building: MapBuilding, report: ReadReport):
    """Settles impossible or contradictory tags before any guessing (rules in docs/guesses.md)."""
    for name in ("height", "min_height", "levels", "min_level", "roof_height", "roof_levels"):
        value = _tag(building, name)
        if value is not None and (not math.isfinite(value) or value < 0):
            _reject(building, name, report, f"{name} below zero or not a number: ignored")
    levels = _tag(building, "levels")
    if levels is not None and levels > MAX_LEVELS:
        _reject(building, "levels", report, f"levels above {MAX_LEVELS}: ignored")
    height = _tag(building, "height")
    if height is not None and height < 1.0:
        _reject(building, "height", report, "height below 1 m: ignored")
    levels = _tag(building, "levels")
    if levels is not None and levels < 1.0 and building.has_walls:
        _reject(building, "levels", report, "levels below 1 on a building with walls: ignored")
    if _tag(building, "min_height") is not None:
        settle_top(building, report)
    levels, min_level = _tag(building, "levels"), _tag(building, "min_level")
    if levels is not None and min_level is not None and levels <= min_level:
        _retag(
            building,
            "levels",
            min_level + levels,
            report,
            "min_level not below levels: levels read as counted from min_level",
        )
    height, roof_height = _tag(building, "height"), _tag(building, "roof_height")
    bottom = _tag(building, "min_height") or 0.0
    if height is not None and roof_height is not None and roof_height > height - bottom:
        _retag(
            building,
            "roof_height",
            height - bottom,
            report,
            "roof_height above the building: cut to the building's height",
        )
    levels = _tag(building, "levels")
    if height is not None and levels and building.kind not in TALL_STOREYS:
        walls = height - (_tag(building, "roof_height") or 0.0) - bottom
        storeys = levels - (_tag(building, "min_level") or 0.0)
        storey = walls / storeys if storeys > 0 else 0.0
        if not STOREY_RANGE[0] <= storey <= STOREY_RANGE[1]:
            # The height is a measurement; the level count is re-derived from it.
            storey = defaults_for(building.kind, building.footprint_area, building.is_part).storey
            levels = (_tag(building, "min_level") or 0.0) + max(1.0, round(walls / storey))
            _retag(building, "levels", levels, report, "levels contradict height: levels derived from the height")
