"""The city a map describes, in local metres: what every stage after the readers works from.

Coordinates are (east, north) metres from `MapData.origin`, a point given in longitude/latitude and
projected with `MapData.crs`. The scene's frame has north toward -z, so a map point (x, y) stands at
scene (x, -y) (see `to_scene`). No file formats and no GL here: readers (OpenStreetMap, GeoJSON,
CityJSON) fill these records, the guessing model fills what the map left out, and the scene builder
turns them into meshes.

Every attribute a record gets either came from the data (its name is in `tagged`) or was invented
(its name is in `guessed`); an attribute is in exactly one of the two sets once guessing has run.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shapely

from ..scene import ROOF_SHAPE_TABLE
from ..terrain import Terrain

# Roof shapes of the Simple 3D Buildings scheme that cityshade builds (OpenStreetMap `roof:shape` values).
ROOF_SHAPES = tuple(ROOF_SHAPE_TABLE)

# The attributes whose origin (tagged or guessed) a building record keeps.
BUILDING_ATTRIBUTES = (
    "height",
    "min_height",
    "levels",
    "min_level",
    "roof_shape",
    "roof_height",
    "roof_levels",
    "roof_direction",
    "roof_orientation",
    "building_colour",
    "roof_colour",
    "building_material",
    "roof_material",
)
TREE_ATTRIBUTES = ("height", "crown_diameter", "leaf_type", "genus")

AREA_KINDS = ("water", "grass", "park", "forest", "meadow", "pavement", "sand", "farmland")


@dataclass
class MapBuilding:
    """A building outline or a `building:part`, with its Simple 3D Buildings attributes.

    Heights are metres above the ground: walls run from `min_height` to `height - roof_height`,
    the roof from there to `height`. `None` means neither the data nor the guessing model has
    given the value yet (the guessing model leaves no `None` in numeric fields it owns).
    """

    index: int  # position in MapData.buildings
    source_id: str  # "way/123", "relation/456", a GeoJSON feature id or a CityJSON object id
    outline: shapely.Polygon  # map metres, exterior counter-clockwise, holes for courtyards
    kind: str = "yes"  # the value of building=* (or building:part=*)
    is_part: bool = False
    parent: int | None = None  # for parts: the index of the outline they belong to
    has_walls: bool = True  # False for building=roof (a canopy on pillars)
    replaced_by_parts: bool = False  # an outline whose parts are drawn instead of it
    # An outline its parts cover only in part: the (Multi)Polygon where no part stands (empty if none),
    # drawn instead of `outline` (with the outline's tags) so that its walls never stand where a part's do;
    # and the pieces of it under parts that float (min_height/min_level), each drawn up to that part's base.
    remainder: shapely.Geometry | None = None
    beneath_parts: list[tuple[shapely.Geometry, MapBuilding]] = field(default_factory=list)
    height: float | None = None
    min_height: float | None = None
    levels: float | None = None
    min_level: float | None = None
    roof_shape: str | None = None
    roof_height: float | None = None
    roof_levels: float | None = None
    roof_direction: float | None = None  # degrees clockwise from north that the main roof face looks (OSM)
    roof_orientation: str | None = None  # "along" or "across" the longest side
    roof_angle: float | None = None  # degrees
    building_colour: tuple[float, float, float] | None = None  # sRGB 0..1
    roof_colour: tuple[float, float, float] | None = None
    building_material: str | None = None
    roof_material: str | None = None
    use: str | None = None  # what the building is used for (from building=*, shop, amenity, office)
    # A shed, sauna, garage, kiosk, tank or any footprint under ~30 m² whose size the map does not give:
    # one storey, no interior rooms, a door and few or no windows (set by the guessing model).
    small_utility: bool = False
    # Shops on the ground floor: `shop=*` on the building, or a shop mapped as a point inside it.
    shop_front: bool = False
    # Door points on the outline (map metres), the main entrance first: mapped `entrance=*` nodes
    # ("doors" in `tagged`), else one on the street side placed by the guessing model ("doors" in `guessed`).
    doors: list[tuple[float, float]] = field(default_factory=list)
    tags: dict[str, str] = field(default_factory=dict)
    tagged: set[str] = field(default_factory=set)
    guessed: set[str] = field(default_factory=set)
    # For the sizes and roof the guessing model estimated ("levels", "height", "roof_shape"): the chance,
    # 0..1, that the guess is right (levels within one storey, height within 3 m, roof flat or pitched).
    confidence: dict[str, float] = field(default_factory=dict)
    # The form the guessing model recognised from the outline and its neighbours: row_house, terrace_house,
    # semi_detached, shed, tower, or "" (none of them).
    form: str = ""
    # CityJSON only: the faces as given by semantic type ("RoofSurface", "WallSurface", "GroundSurface", ...;
    # "unclassified" without semantics), each face's outer ring as (n, 3) map metres, z the height as given
    # (above the file's vertical datum); `ground`: the height as given of the building's lowest point.
    surfaces: dict[str, list[np.ndarray]] | None = None
    ground: float = 0.0
    lod: str | None = None  # the CityJSON level of detail drawn

    @property
    def footprint_area(self) -> float:
        return float(self.outline.area)

    @property
    def drawn(self) -> bool:
        return not self.replaced_by_parts

    @property
    def drawn_footprint(self) -> shapely.Geometry:
        """Where the building's mass stands: its outline, or what of it no part stands on."""
        return self.outline if self.remainder is None else self.remainder


@dataclass
class Road:
    """A street or path centreline (`highway=*`)."""

    source_id: str
    line: shapely.LineString  # map metres
    kind: str  # the highway value: primary, residential, footway, ...
    width: float  # metres, carriageway including lanes
    lanes: int | None = None
    layer: int = 0
    bridge: bool = False
    tunnel: bool = False
    lit: bool = False
    oneway: bool = False
    sidewalk: str | None = None  # both, left, right, no
    tags: dict[str, str] = field(default_factory=dict)


@dataclass
class Railway:
    """A railway or tram line (`railway=rail|tram|light_rail|subway|...`)."""

    source_id: str
    line: shapely.LineString
    kind: str
    gauge: float = 1.524  # metres (Finnish broad gauge; 1.435 standard)
    layer: int = 0
    bridge: bool = False
    tunnel: bool = False
    tags: dict[str, str] = field(default_factory=dict)


@dataclass
class Area:
    """A surface on the ground: water, grass, park, forest, ... (one of AREA_KINDS)."""

    source_id: str
    polygon: shapely.Polygon
    kind: str
    tags: dict[str, str] = field(default_factory=dict)


@dataclass
class MapTree:
    """A single tree (`natural=tree`, a tree of a `tree_row`, or one planted in a wood)."""

    source_id: str
    position: tuple[float, float]  # map metres
    height: float | None = None
    crown_diameter: float | None = None
    leaf_type: str | None = None  # broadleaved, needleleaved
    genus: str | None = None
    species: str | None = None
    tagged: set[str] = field(default_factory=set)
    guessed: set[str] = field(default_factory=set)


@dataclass
class Lamp:
    """A street lamp (`highway=street_lamp`, one placed along a lit road, or one guessed)."""

    source_id: str
    position: tuple[float, float]
    height: float = 6.0
    from_lit_road: bool = False
    guessed: bool = False  # placed where the map is silent (maps/features/lamps.py)


@dataclass
class Entrance:
    """A mapped door (`entrance=*` node): main, yes, staircase, service, shop, ..."""

    source_id: str
    position: tuple[float, float]  # map metres
    kind: str


@dataclass
class CityObject:
    """A CityJSON city object that is no building (Road, LandUse, PlantCover, WaterBody, Bridge, ...),
    drawn as given: its faces' outer rings (n, 3) in map metres with heights as given."""

    source_id: str
    type: str
    kind: str | None  # its `class`, `function` or `usage` attribute, when given
    faces: list[tuple[str | None, np.ndarray]]  # (semantic surface type or None, ring)
    lod: str | None = None
    attributes: dict = field(default_factory=dict)


@dataclass
class ReadReport:
    """What a reader repaired, skipped or fell back on, counted by (what, why)."""

    repaired: Counter = field(default_factory=Counter)
    skipped: Counter = field(default_factory=Counter)
    fallbacks: Counter = field(default_factory=Counter)  # unreadable tag values replaced by defaults
    examples: dict[tuple[str, str], str] = field(default_factory=dict)  # first element id per reason

    def _note(self, counter: Counter, what: str, why: str, element: str | None):
        counter[(what, why)] += 1
        if element is not None:
            self.examples.setdefault((what, why), element)

    def repair(self, what: str, why: str, element: str | None = None):
        self._note(self.repaired, what, why, element)

    def skip(self, what: str, why: str, element: str | None = None):
        self._note(self.skipped, what, why, element)

    def fallback(self, what: str, why: str, element: str | None = None):
        self._note(self.fallbacks, what, why, element)


@dataclass
class MapData:
    """Everything read from one map file, projected to local metres."""

    source: Path
    origin: tuple[float, float]  # longitude, latitude of map point (0, 0)
    crs: str  # the projection used, e.g. "EPSG:32635" (UTM zone 35N)
    buildings: list[MapBuilding] = field(default_factory=list)
    roads: list[Road] = field(default_factory=list)
    railways: list[Railway] = field(default_factory=list)
    areas: list[Area] = field(default_factory=list)
    trees: list[MapTree] = field(default_factory=list)
    lamps: list[Lamp] = field(default_factory=list)
    entrances: list[Entrance] = field(default_factory=list)
    shops: list[tuple[float, float]] = field(default_factory=list)  # shops mapped as points (map metres)
    report: ReadReport = field(default_factory=ReadReport)
    declared_bounds: tuple[float, float, float, float] | None = None  # the file's own extent (OSM <bounds>)
    # CityJSON: the city objects that are no buildings, what was drawn (type -> objects) and the lowest
    # ground as given, where the land plane lies (heights are kept as the file gives them)
    city_objects: list[CityObject] = field(default_factory=list)
    drawn_types: Counter = field(default_factory=Counter)
    ground_level: float = 0.0
    terrain: Terrain | None = None  # the ground's relief (--terrain); None: the map is flat

    @property
    def name(self) -> str:
        return self.source.name.split(".")[0]

    def bounds(self) -> tuple[float, float, float, float]:
        """(min x, min y, max x, max y) in map metres over buildings, roads and areas."""
        geometries = (
            [b.outline for b in self.buildings] + [r.line for r in self.roads] + [a.polygon for a in self.areas]
        )
        rings = [ring[:, :2] for obj in self.city_objects for _, ring in obj.faces]
        if rings:
            points = np.vstack(rings)
            geometries.append(shapely.multipoints([points.min(axis=0), points.max(axis=0)]))
        if not geometries:
            return (0.0, 0.0, 0.0, 0.0)
        return tuple(float(v) for v in shapely.total_bounds(geometries))


def to_scene(points) -> np.ndarray:
    """Map (east, north) metres -> scene (x, z) with north toward -z."""
    points = np.asarray(points, dtype=np.float64)
    return np.stack([points[..., 0], -points[..., 1]], axis=-1)
