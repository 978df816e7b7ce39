"""Map buildings -> building masses: one turned object space per outline, walls between min_height
and the roof, courtyards, floating parts, roofs, tints and a facade style by use.

An outline its building:part ways cover in part stands only where no part does (`remainder`), one
mass per piece, and under parts that float (`beneath_parts`) up to their base, with a flat roof
and no parapet (the part stands on it). A pitched roof was mapped for the whole outline: on a piece
that is still about a rectangle (RECTANGLE_FILL of its minimum rotated rectangle) the roof is built
over the piece; on any other cut shape it would no longer fit, and the piece gets a flat roof at
the eaves the pitched roof would have had.

Values the map left out are normally filled by the guessing model before this runs; where one is
still missing, the same documented per-type defaults (`defaults_for`) are used."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from ..scene import LEVEL_CODES, USES, BuildingMass, Roof
from ._defaults import defaults_for
from ._doors import mass_doors
from ._given import given_mass
from ._model import MapBuilding, MapData, to_scene
from ._roofs import building_roof

MIN_THICKNESS = 0.05  # metres between a mass's bottom and top
MIN_AREA = 1.0  # square metres; smaller outlines are slivers, not buildings
FLOOR_HEIGHT_RANGE = (2.5, 6.0)
LEVEL_MASK = LEVEL_CODES["LEVEL_MASK"]  # the highest first level a record holds
CANOPY_MIN_HEIGHT = 2.5  # building=roof with nothing tagged: a roof on pillars this high
RECTANGLE_FILL = 0.9  # a cut piece filling this much of its minimum rotated rectangle keeps a pitched roof

# Building style numbers (0..7) by what a building is used for. The facade registry turns a style
# into a facade (cityshade.render.choose_facade): 0 the window bay with rooms, 1 the office grammar
# (glass), 3 classical, 4 brick, 5 shop fronts, 6 dusk, 7 fig12; 2 the relief bay on box buildings.
STYLE_BY_USE = {
    "residential": 0,
    "apartments": 0,
    "dormitory": 0,
    "house": 4,
    "detached": 4,
    "terrace": 4,
    "semidetached_house": 4,
    "bungalow": 4,
    "cabin": 4,
    "commercial": 5,
    "retail": 5,
    "shop": 5,
    "supermarket": 5,
    "kiosk": 5,
    "hotel": 6,
    "office": 1,
    "industrial": 4,
    "warehouse": 4,
    "factory": 4,
    "garage": 4,
    "garages": 4,
    "shed": 4,
    "hangar": 4,
    "civic": 3,
    "public": 3,
    "government": 3,
    "school": 3,
    "university": 3,
    "college": 3,
    "hospital": 3,
    "church": 3,
    "cathedral": 3,
    "chapel": 3,
    "mosque": 3,
    "synagogue": 3,
    "temple": 3,
    "museum": 3,
    "train_station": 3,
    "transportation": 3,
}
STYLES = 8

# What decides when a building's rooms are lit (cityshade.scene.LIT_SCHEDULE), by its use or kind;
# anything else (building=yes with no use) is "mixed".
USE_BY_KIND = {
    **dict.fromkeys(
        (
            "residential",
            "apartments",
            "dormitory",
            "house",
            "detached",
            "terrace",
            "semidetached_house",
            "bungalow",
            "cabin",
            "farm",
            "hotel",
        ),
        "home",
    ),
    **dict.fromkeys(("office", "bank"), "office"),
    **dict.fromkeys(
        ("commercial", "retail", "shop", "supermarket", "kiosk", "restaurant", "cafe", "bar", "pub", "fast_food"),
        "shop",
    ),
    **dict.fromkeys(("industrial", "warehouse", "factory", "manufacture"), "industry"),
    **dict.fromkeys(
        (
            "civic",
            "public",
            "government",
            "school",
            "kindergarten",
            "university",
            "college",
            "hospital",
            "church",
            "cathedral",
            "chapel",
            "mosque",
            "synagogue",
            "temple",
            "place_of_worship",
            "museum",
            "library",
            "townhall",
            "train_station",
            "transportation",
        ),
        "public",
    ),
}


def facade_style(building: MapBuilding) -> int:
    """The facade style (0..7) for a building's use or kind; unknown uses get a stable varied one."""
    if building.small_utility:
        return STYLE_BY_USE["shed"]  # whatever its tag says, a small outbuilding looks like a shed
    if building.shop_front:
        return STYLE_BY_USE["shop"]  # shop fronts on the ground floor, storeys of windows above
    for use in (building.use, building.kind):
        if use in STYLE_BY_USE:
            return STYLE_BY_USE[use]
    whole = building.parent if building.is_part and building.parent is not None else building.index
    return int(whole) % STYLES  # the parts of one building share the outline's


def use_code(building: MapBuilding) -> int:
    """The building's USE_* code (cityshade.scene.USES) from its use, else its kind."""
    return USES[next((USE_BY_KIND[use] for use in (building.use, building.kind) if use in USE_BY_KIND), "mixed")]


def heights(building: MapBuilding) -> tuple[float, float, float]:
    """(min height, height, floor height) in metres, with the fallbacks where values are missing."""
    defaults = defaults_for(building.kind)
    levels = building.levels
    height = building.height
    if height is None:
        height = (levels if levels is not None else defaults.levels) * defaults.storey + (building.roof_height or 0.0)
    base = building.min_height
    if base is None:
        base = (building.min_level or 0.0) * defaults.storey
    if not building.has_walls and building.min_height is None:
        base = min(height, CANOPY_MIN_HEIGHT)
    walls = height - (building.roof_height or 0.0) - base
    floor = (
        walls / (levels - (building.min_level or 0.0))
        if levels and levels > (building.min_level or 0.0)
        else defaults.storey
    )
    return float(base), float(height), float(np.clip(floor, *FLOOR_HEIGHT_RANGE))


def first_level(building: MapBuilding, base: float, floor: float) -> int:
    """The storey a mass's walls start at (its facade.level): its building:min_level (the maps guess
    it from min_height over the storey height where it is not tagged), else its base over its floor height."""
    level = building.min_level if building.min_level is not None else base / floor
    return int(np.clip(round(level), 0, LEVEL_MASK))


def _frame(polygon: shapely.Polygon) -> tuple[float, np.ndarray]:
    """(yaw, offset): the object space turned to the minimum rotated rectangle's longest side."""
    rectangle = np.asarray(polygon.minimum_rotated_rectangle.exterior.coords)[:4]
    edges = np.diff(np.vstack([rectangle, rectangle[:1]]), axis=0)
    longest = edges[np.argmax(np.linalg.norm(edges, axis=1))]
    return float(np.arctan2(-longest[1], longest[0])), rectangle


def _to_local(points: np.ndarray, yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack([c * points[:, 0] - s * points[:, 1], s * points[:, 0] + c * points[:, 1]], axis=1)


def _polygons(outline) -> list[shapely.Polygon]:
    """Scene-space polygons of an outline (map metres), repaired where invalid."""
    scene = shapely.transform(outline, to_scene)
    if not scene.is_valid:
        scene = shapely.make_valid(scene)
    parts = getattr(scene, "geoms", [scene])
    return [p for p in parts if isinstance(p, shapely.Polygon) and p.area >= MIN_AREA]


def _fits_pitched_roof(polygon: shapely.Polygon) -> bool:
    return not polygon.interiors and polygon.area >= RECTANGLE_FILL * polygon.minimum_rotated_rectangle.area


def building_mass(
    building: MapBuilding,
    polygon: shapely.Polygon,
    cut: bool = False,
    top: float | None = None,
    style: int | None = None,
) -> BuildingMass | None:
    """One building (or part) standing on one scene-space polygon; None if it has no volume. `cut`: the
    polygon is a piece of an outline beside its parts (a pitched roof that no longer fits becomes flat);
    `top`: a piece under a floating part, ending flat at that height; `style`: its facade style (its
    building's, for a part), else its own."""
    style = facade_style(building) if style is None else style
    base, height, floor = heights(building)
    if top is not None:
        height = min(height, top)
    if height - base <= MIN_THICKNESS:
        return None  # a part whose bottom is at or above its top: nothing to draw
    polygon = shapely.orient_polygons(polygon)  # positive area in (x, z): walls face out
    yaw, _ = _frame(polygon)
    exterior = _to_local(np.asarray(polygon.exterior.coords)[:-1], yaw)
    low = exterior.min(axis=0)
    exterior -= low
    holes = tuple(
        tuple(map(tuple, (_to_local(np.asarray(r.coords)[:-1], yaw) - low).tolist())) for r in polygon.interiors
    )
    c, s = np.cos(yaw), np.sin(yaw)
    origin = (float(c * low[0] + s * low[1]), float(-s * low[0] + c * low[1]))
    local = shapely.Polygon(exterior, [np.asarray(h) for h in holes])
    doors = (
        mass_doors(_to_local(to_scene(building.doors), yaw) - low, local)
        if building.doors and base <= 0 and building.has_walls
        else ()
    )
    roof = building_roof(building, local, yaw, height - base, floor)
    if building.surfaces is not None:  # faces as given: the roof's material, not its shape
        flat = Roof(colour=roof.colour, material=roof.material, seed=roof.seed)
        return given_mass(building, polygon, (yaw, low, _to_local), style, use_code(building), flat)
    if top is not None:
        roof = Roof(colour=roof.colour, material=roof.material, seed=roof.seed)  # flat, no parapet
    elif cut and roof.height > 0 and not _fits_pitched_roof(polygon):
        height -= roof.height  # flat at the eaves the mapped roof would have had
        roof = building_roof(replace(building, roof_shape="flat"), local, yaw, height - base, floor)
    if height - roof.height - base <= MIN_THICKNESS and building.has_walls:
        return None
    return BuildingMass(
        "prism",
        origin,
        tuple(map(tuple, exterior.tolist())),
        height,
        yaw=yaw,
        floor_height=floor,
        seed=building.index,
        style=style,
        use=use_code(building),
        shop_front=building.shop_front,
        holes=holes,
        base=base,
        first_level=first_level(building, base, floor),
        roof=roof,
        walls=building.has_walls,
        doors=doors,
        wall_colour=building.building_colour,
        wall_material=building.building_material,
        guessed=frozenset(building.guessed),
        # A shed or sauna: no rooms behind its few windows, only dark panes.
        **({"interior": False, "furniture": False, "curtains": False, "lights": 0.0} if building.small_utility else {}),
    )


def _in_its_outlines_colour(part: MapBuilding, outline: MapBuilding | None) -> MapBuilding:
    """A building part whose wall colour and material the map does not give wears its outline's
    (tagged or guessed once for the whole building), so one building's parts do not each get a colour
    of their own; a part whose tags say otherwise keeps them."""
    if outline is None or not part.is_part or not {"building_colour", "building_material"} <= part.guessed:
        return part
    return replace(part, building_colour=outline.building_colour, building_material=outline.building_material)


def _style_owner(map_data: MapData, building: MapBuilding) -> MapBuilding:
    """Whose facade style a building takes: a CityJSON part its building's, unless its attributes give
    its own use (or the data at hand does not hold its building)."""
    parent = building.parent
    if building.surfaces is None or not building.is_part or parent is None:
        return building
    if building.use in STYLE_BY_USE or building.kind in STYLE_BY_USE:
        return building
    held = 0 <= parent < len(map_data.buildings) and map_data.buildings[parent].index == parent
    return map_data.buildings[parent] if held else building


def building_masses(map_data: MapData) -> list[BuildingMass]:
    """The masses of every drawn building and part (outlines replaced by their parts are skipped, those
    cut by them stand on their remainder and under their floating parts)."""
    masses = []
    by_index = {b.index: b for b in map_data.buildings}
    for building in map_data.buildings:
        if not building.drawn:
            continue
        building = _in_its_outlines_colour(building, by_index.get(building.parent))
        pieces = [(polygon, None) for polygon in _polygons(building.drawn_footprint)]
        for under, part in building.beneath_parts:
            pieces += [(polygon, heights(part)[0]) for polygon in _polygons(under)]
        owner = _style_owner(map_data, building)
        ground = seat(map_data, building, by_index)
        for polygon, top in pieces:
            mass = building_mass(building, polygon, building.remainder is not None, top, facade_style(owner))
            if mass is not None:
                masses.append(
                    mass if ground == 0.0 else replace(mass, base=mass.base + ground, height=mass.height + ground)
                )
    return masses


def seat(map_data: MapData, building: MapBuilding, by_index: dict[int, MapBuilding]) -> float:
    """The ground a building stands on: the lowest terrain along its outline (a part's: its
    building's, so the parts of one building share one base); its walls reach down to it on the
    downhill side and min_height counts from it. 0 without terrain, and for faces as given."""
    if map_data.terrain is None or building.surfaces is not None:
        return 0.0
    root = by_index.get(building.parent, building) if building.is_part else building
    return map_data.terrain.lowest_on(root.outline)
