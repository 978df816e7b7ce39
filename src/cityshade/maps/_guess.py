"""`guess_missing(map_data)`: a copy of the map with every attribute it left out filled and flagged as guessed.

Kept apart from the readers so it can be replaced: it only reads the records' tagged values and
outlines. Order: settle contradictory tags (`_defaults.resolve_contradictions`), estimate levels,
storey height and roof shape per building (the learned model in `_learn.py`, which falls back to
the regional defaults where the map tags nothing), then derive the rest from the outline's form.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import functools
import gc
import math
import zlib
from collections import Counter

import numpy as np

from ..scene import roof_material
from ._defaults import (
    DEFAULT_ROOF_ANGLE,
    HOUSE,
    MATERIAL_COLOURS,
    SMALL_FOOTPRINT,
    resolve_contradictions,
    settle_top,
)
from ._doors import place_doors
from ._form import Form, urban_form
from ._learn import Estimates, Prior, estimate, load_prior, regional_defaults
from ._model import MapBuilding, MapData, MapTree, ReadReport

ROOF_ANGLES = {"skillion": 15.0, "gambrel": 45.0, "mansard": 50.0, "cone": 45.0, "onion": 60.0}
ATTIC = 2.2  # metres of roof height a person can stand in: one roof level
HEIGHT_TOLERANCE = 3.0  # metres: a guessed height this close to the truth counts as right (its confidence)
LOWEST_STOREY = 2.5  # metres: a guessed roof leaves at least this much to each tagged storey

NEEDLELEAVED = {"Pinus", "Picea", "Abies", "Larix", "Juniperus", "Taxus", "Thuja", "Pseudotsuga", "Cedrus"}
TREE_DEFAULTS = {  # leaf type -> (genus, height m, crown diameter / height)
    "broadleaved": ("Tilia", 12.0, 0.6),
    "needleleaved": ("Picea", 15.0, 0.4),
}


def guess_missing(read: MapData, prior: Prior | None = None, learn: bool = True) -> MapData:
    """A copy of the map with every attribute of every building and tree that was None filled (its name
    added to `guessed`), and a door on the street side of buildings without a mapped entrance
    (`place_doors`); `read` stays as it was read.

    Contradictory tags are settled first by the documented rules and counted in the copy's report.
    Deterministic: the same map gives the same guesses. `prior`: the models learnt from other cities
    (`load_prior()`, the shipped one, by default). `learn=False`: the regional defaults of each
    building's type, size and form alone (what `bench guesses` compares the model with).
    """
    with _collector_paused():
        map_data = _copy_to_guess(read)
        for building in map_data.buildings:
            resolve_contradictions(building, map_data.report)
        if map_data.buildings:
            form = urban_form(map_data)
            if learn:
                estimates = estimate(map_data.buildings, form, prior or load_prior())
            else:
                estimates = regional_defaults(map_data.buildings, form)
            for i, building in enumerate(map_data.buildings):
                building.form = str(form.forms[i])
                _fill_building(building, estimates, form, i, map_data.report)
        place_doors(map_data)
        _guess_trees(map_data.trees)
    return map_data


@contextlib.contextmanager
def _collector_paused():
    """Python's cyclic garbage collector off while guessing makes its records: it would rescan every
    record made so far again and again (measured on 100,000 buildings: 1.3 s to copy them without
    it, 6-8 s with it). Any cycle made meanwhile is collected on the collector's next run."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _copy_to_guess(read: MapData) -> MapData:
    """A copy of `read` that guessing may fill without touching `read`: every record copied with
    its own lists, dicts and sets, the geometry shared (shapely's is immutable; the faces as given,
    CityJSON, are made read-only here). A deepcopy spent a third of the guessing time pickling
    outlines and faces."""
    for group in (b.surfaces for b in read.buildings if b.surfaces):
        for ring in (r for rings in group.values() for r in rings):
            ring.flags.writeable = False
    for ring in (r for o in read.city_objects for _, r in o.faces):
        ring.flags.writeable = False
    buildings = [_record_copy(b) for b in read.buildings]
    twin = {id(old): new for old, new in zip(read.buildings, buildings)}
    for building in buildings:  # the parts a building is drawn beneath are the copies' parts
        building.beneath_parts = [(under, twin[id(part)]) for under, part in building.beneath_parts]
    records = {
        name: [_record_copy(r) for r in getattr(read, name)]
        for name in ("roads", "railways", "areas", "trees", "lamps", "entrances", "city_objects")
    }
    return dataclasses.replace(_record_copy(read), buildings=buildings, report=copy.deepcopy(read.report), **records)


def _record_copy(record):
    """A shallow copy of a dataclass record with copies of its list, dict and set fields."""
    fresh = object.__new__(type(record))  # copy.copy's __reduce_ex__ took most of the copying time
    fresh.__dict__.update(record.__dict__)
    for name in _container_fields(type(record)):
        setattr(fresh, name, copy.copy(getattr(record, name)))
    return fresh


@functools.cache
def _container_fields(record_type: type) -> tuple[str, ...]:
    """The fields of a record type that hold a list, dict or set (their default factories say so)."""
    factories = (list, dict, set, Counter)
    return tuple(f.name for f in dataclasses.fields(record_type) if f.default_factory in factories)


def _set(building: MapBuilding, name: str, value):
    setattr(building, name, value)
    building.guessed.add(name)


def _fill_building(building: MapBuilding, estimates: Estimates, form: Form, i: int, report: ReadReport):
    """Every missing attribute, in the order they depend on each other: the roof's shape and height,
    the storeys and heights, the roof's geometry, the materials and colours."""
    defaults = form.defaults[i]
    small = defaults.small or (form.area[i] < SMALL_FOOTPRINT and not building.is_part)  # small parts are turrets
    storey = float(estimates.storey[i])
    if small and "levels" not in building.tagged and "height" not in building.tagged:
        building.small_utility = True
    _fill_roof(building, estimates, form, i, storey)
    pitched = building.roof_shape != "flat"
    flat_house = defaults is HOUSE and "roof_shape" in building.tagged and not pitched
    _fill_levels_and_heights(building, estimates, i, storey, small, flat_house, report)
    _fill_roof_geometry(building, form, i, pitched)
    _fill_materials(building, defaults, pitched)


def _fill_roof(building: MapBuilding, estimates: Estimates, form: Form, i: int, storey: float):
    if building.roof_shape is None:
        roof = str(estimates.roof_shape[i])
        if roof == "flat" and (building.roof_height or building.roof_levels):
            roof = "gabled"  # a tagged roof height says the roof is not flat
        _set(building, "roof_shape", roof)
        if np.isfinite(estimates.roof_confidence[i]):
            building.confidence["roof_shape"] = float(estimates.roof_confidence[i])
    if building.roof_height is None and building.roof_levels is not None:
        _set(building, "roof_height", building.roof_levels * storey)
    if building.roof_height is None:
        roof_height = _roof_height(building, form.short_side[i])
        if building.height is not None and building.levels is not None:
            # The tagged storeys keep at least LOWEST_STOREY each under a guessed roof.
            storeys = building.levels - (building.min_level or 0.0)
            room = building.height - (building.min_height or 0.0) - storeys * LOWEST_STOREY
            roof_height = min(roof_height, max(room, 0.0))
        _set(building, "roof_height", roof_height)


def _fill_levels_and_heights(
    building: MapBuilding, estimates: Estimates, i: int, storey: float, small: bool, flat_house: bool, report
):
    if building.min_level is None:
        min_level = float(round(building.min_height / storey)) if building.min_height else 0.0
        if building.levels is not None:
            min_level = min(min_level, building.levels - 1.0)  # the guess yields to tagged levels
        _set(building, "min_level", max(min_level, 0.0))
    if building.min_height is None:
        _set(building, "min_height", building.min_level * storey)
        settle_top(building, report)
    if building.height is None and building.levels is None and not small and np.isfinite(estimates.block_height[i]):
        _set(
            building, "height", max(float(estimates.block_height[i]), building.min_height + building.roof_height + 2.0)
        )
    if building.levels is None:
        if building.height is not None:
            walls = max(building.height - building.roof_height - building.min_height, 0.0)
            levels = building.min_level + max(1.0, float(round(walls / storey)))
        elif building.small_utility:
            levels = 1.0
        elif flat_house:
            levels = 2.0  # a flat-roofed house has its second storey under the flat roof
        else:
            levels = max(1.0, float(estimates.levels[i]))
            if np.isfinite(estimates.levels_confidence[i]):
                building.confidence["levels"] = float(estimates.levels_confidence[i])
        _set(building, "levels", max(levels, building.min_level + 1.0))
    if building.height is None:
        wall_height = max(building.levels - building.min_level, 1.0) * storey
        _set(building, "height", building.min_height + wall_height + building.roof_height)
        # Metres of typical error: the level count's spread in storeys, else a tenth of the storey height.
        spread = estimates.levels_spread[i] if "levels" in building.guessed else 0.1 * building.levels
        if np.isfinite(spread):
            building.confidence["height"] = float(1.0 - np.exp(-HEIGHT_TOLERANCE / max(spread * storey, 0.05)))
    # Never a negative or empty volume: the roof fits between the bottom and the top.
    building.roof_height = min(building.roof_height, max(building.height - building.min_height, 0.0))


def _fill_roof_geometry(building: MapBuilding, form: Form, i: int, pitched: bool):
    if building.roof_levels is None:
        _set(building, "roof_levels", 1.0 if pitched and building.roof_height >= ATTIC else 0.0)
    if building.roof_angle is None:
        half_width = max(form.short_side[i] / 2, 0.5)
        _set(building, "roof_angle", math.degrees(math.atan2(building.roof_height, half_width)) if pitched else 0.0)
    if building.roof_orientation is None:
        _set(building, "roof_orientation", "along")
    if building.roof_direction is None:
        # roof:direction is where the main face looks: across the ridge, which runs along the
        # longest side unless the orientation says across
        facing = 0.0 if building.roof_orientation == "across" else 90.0
        _set(building, "roof_direction", float((form.long_bearing[i] + facing) % 360.0))


def _fill_materials(building: MapBuilding, defaults, pitched: bool):
    if building.building_material is None:
        _set(building, "building_material", defaults.material)
    if building.roof_material is None:
        # felt covers flat roofs: a pitched roof on a type whose roof is flat by default (a block of
        # flats guessed gabled) takes the Nordic pitched cover, a house's sheet metal
        pitched_cover = defaults.roof_material if defaults.roof_shape != "flat" else HOUSE.roof_material
        _set(building, "roof_material", pitched_cover if pitched else "roofing_felt")
    if building.building_colour is None:
        _set(building, "building_colour", _palette(building.building_material, building.source_id))
    if building.roof_colour is None:
        _set(building, "roof_colour", _roof_palette(building.roof_material, building.source_id + "/roof"))


def _roof_height(building: MapBuilding, short_side: float) -> float:
    if building.roof_shape == "flat":
        return 0.0
    half_width = short_side / 2
    if building.roof_shape in ("dome", "round"):
        return float(min(half_width, 12.0))
    angle = (
        building.roof_angle
        if building.roof_angle is not None
        else ROOF_ANGLES.get(building.roof_shape, DEFAULT_ROOF_ANGLE)
    )
    rise = half_width * math.tan(math.radians(min(angle, 75.0)))
    if building.roof_shape == "skillion":
        rise *= 2  # one slope across the whole width
    return float(min(rise, 12.0))


def _palette(material: str, key: str) -> tuple[float, float, float]:
    """A colour for the material, chosen by the element id so neighbours differ but reruns agree."""
    colours = MATERIAL_COLOURS.get(material, MATERIAL_COLOURS["plaster"])
    return colours[zlib.crc32(key.encode()) % len(colours)]


def _roof_palette(material: str, key: str) -> tuple[float, float, float]:
    """A roof colour for the material: from the palette where it has one, else the roof
    material's own colour (tiles red, slate dark grey, copper green...), not a plaster's."""
    if material in MATERIAL_COLOURS:
        return _palette(material, key)
    _, colour = roof_material(material)
    return tuple(float(c) for c in colour)


def _guess_trees(trees: list[MapTree]):
    for tree in trees:
        if tree.leaf_type is None:
            _set(tree, "leaf_type", "needleleaved" if tree.genus in NEEDLELEAVED else "broadleaved")
        genus, height, crown_ratio = TREE_DEFAULTS.get(tree.leaf_type, TREE_DEFAULTS["broadleaved"])
        if tree.genus is None:
            _set(tree, "genus", genus)
        if tree.height is None:
            _set(tree, "height", tree.crown_diameter / crown_ratio if tree.crown_diameter else height)
        if tree.crown_diameter is None:
            _set(tree, "crown_diameter", tree.height * crown_ratio)
