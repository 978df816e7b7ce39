"""Features of urban form for every building of a map, computed at once (shapely 2 array functions, numpy).

One row per building, one column per name in FEATURES: the outline's size and shape, the walls it
shares, the footprints around it (within 50 and 100 m), the block it stands in, the street it faces,
its type and use, its parts and the tagged sizes of the buildings around it. Missing
values are NaN (the gradient boosting in `_learn.py` takes them as missing). The model predicts from
these; the rules that name a form (row house, shed, tower) read them too (`forms`).

Everything is bulk queries on STRtrees and bincounts over the pairs they return, so the cost grows
about linearly with the number of buildings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ._defaults import DEFAULTS, GENERIC, HOUSE, SMALL_FOOTPRINT, SMALL_WOOD, TypeDefaults, defaults_for
from ._model import MapBuilding, MapData

TOUCHING = 1.0  # metres: outlines this close share a wall (the same block)
NEAR, FAR = 50.0, 100.0  # metres: the two rings of neighbouring footprints
STREET_REACH = 60.0  # metres: the street a building faces is the nearest one this close
TAG_RADIUS = 250.0  # metres: tagged buildings this close inform the neighbours' tagged sizes
TAG_CELL = 20.0  # metres: the grid on which the tagged neighbours are summed
TAG_HALF_WEIGHT = 120.0  # metres at which a tagged neighbour's weight halves
MAX_GRID = 3072  # cells a side at most: wider extracts are summed on a coarser grid

# highway=* -> rank of the street a building faces (0: paths only).
STREET_RANKS = {
    "motorway": 6,
    "trunk": 6,
    "primary": 5,
    "secondary": 4,
    "tertiary": 3,
    "residential": 2,
    "unclassified": 2,
    "living_street": 1,
    "service": 1,
    "pedestrian": 1,
}
# building=* values the model knows as categories (any other value is missing, read through its defaults).
KINDS = tuple(sorted(set(DEFAULTS) | {"tower", "hangar", "water_tower", "temple", "mosque", "hut", "construction"}))
KIND_CODES = {kind: code for code, kind in enumerate(KINDS)}

FEATURES = (
    "log_area",
    "log_perimeter",
    "compactness",
    "log_elongation",
    "short_side",
    "long_side",
    "orientation_cos",
    "orientation_sin",
    "vertices",
    "touching",
    "shared_wall_share",
    "block_buildings",
    "log_block_area",
    "nearest_m",
    "count_50",
    "count_100",
    "mean_log_area_50",
    "mean_log_area_100",
    "built_share_100",
    "street_rank",
    "street_m",
    "kind",
    "log_default_levels",
    "default_flat",
    "shop",
    "amenity",
    "is_part",
    "parts",
    "part_share",
    "levels_around",
    "levels_around_weight",
    "levels_block",
    "levels_block_count",
    "levels_around_ratio",
    "levels_block_ratio",
    "height_block",
)
CATEGORICAL = ("kind",)

# Forms named from the outline and its neighbours (`forms`), and the regional defaults they stand for.
HOUSING = GENERIC | {"house", "detached", "terrace", "semidetached_house"}
ROW_HOUSE = TypeDefaults(1, 3.0, "gabled", "wood", "metal")  # a Nordic row house: one long outline, one storey
TERRACE_UNIT = TypeDefaults(2, 3.0, "gabled", "brick", "metal")  # one house of a terrace of party walls
FORM_DEFAULTS = {"row_house": ROW_HOUSE, "terrace_house": TERRACE_UNIT, "semi_detached": HOUSE, "shed": SMALL_WOOD}
FORMS = ("row_house", "terrace_house", "semi_detached", "shed", "tower")
ROW_DEPTH = (6.0, 12.5)  # metres: how deep a row house is (blocks of flats are 12-16 m)
ROW_LENGTH = 22.0  # metres: a row house outline at least this long (three homes or more)
UNIT_AREA = (25.0, 220.0)  # m²: one house of a terrace or a semi-detached pair
TOWER_SHARE = 0.25  # a part this small a share of its outline, compact, is a tower


@dataclass
class Form:
    """The feature matrix of a map's buildings and the geometry the guesses reuse."""

    values: np.ndarray  # (buildings, len(FEATURES)) float64, NaN where unknown
    area: np.ndarray
    short_side: np.ndarray
    long_side: np.ndarray
    long_bearing: np.ndarray  # degrees clockwise from north of the long side, in [0, 180)
    default_levels: np.ndarray
    defaults: list[TypeDefaults]  # the regional defaults of each building (by type, size and form)
    forms: np.ndarray  # object array: one of FORMS, or "" for none
    around: TaggedAround  # the neighbour sums, reused for the roof votes and block heights

    def column(self, name: str) -> np.ndarray:
        return self.values[:, FEATURES.index(name)]


def _oriented_sides(boxes: np.ndarray, area: np.ndarray):
    """Long side, short side and the long side's bearing of each outline's minimum rotated rectangle."""
    box = shapely.get_exterior_ring(boxes)
    corners = shapely.get_coordinates(box)
    ring_sizes = shapely.get_num_coordinates(box)
    starts = np.concatenate([[0], np.cumsum(ring_sizes)[:-1]])
    ok = ring_sizes >= 4
    a, b, c = (corners[np.where(ok, starts + k, 0)] for k in (0, 1, 2))
    first, second = b - a, c - b
    len1, len2 = np.hypot(*first.T), np.hypot(*second.T)
    along = np.where((len1 >= len2)[:, None], first, second)
    side = np.sqrt(np.maximum(area, 0.0))
    long_side = np.where(ok, np.maximum(len1, len2), side)
    short_side = np.where(ok, np.minimum(len1, len2), side)
    bearing = np.where(ok, np.degrees(np.arctan2(along[:, 0], along[:, 1])) % 180.0, 0.0)
    return long_side, short_side, bearing


class TaggedAround:
    """Distance-weighted means over the tagged buildings around each building, the building itself left out.

    The surroundings (within TAG_RADIUS) are summed on a grid by one FFT convolution per quantity, so the
    cost does not grow with how many tagged buildings stand near each other; the block (outlines within
    TOUCHING) comes from the touching pairs.
    """

    def __init__(self, centres: np.ndarray, block_i: np.ndarray, block_j: np.ndarray):
        self.count = len(centres)
        extent = float(np.ptp(centres, axis=0).max()) if len(centres) else 0.0
        cell = max(TAG_CELL, extent / MAX_GRID)  # bounded memory however far apart the buildings are
        reach = int(np.ceil(TAG_RADIUS / cell))
        self.cells = np.floor((centres - centres.min(axis=0)) / cell).astype(np.int64) + reach
        shape = tuple(self.cells.max(axis=0) + reach + 1)
        d = np.hypot(*np.meshgrid(np.arange(-reach, reach + 1), np.arange(-reach, reach + 1), indexing="ij")) * cell
        kernel = np.where(d <= TAG_RADIUS, 1.0 / (1.0 + (d / TAG_HALF_WEIGHT) ** 2), 0.0)
        self.own = kernel[reach, reach]
        self.fft_size = tuple(n + 2 * reach for n in shape)
        padded = np.zeros(self.fft_size)
        padded[: kernel.shape[0], : kernel.shape[1]] = kernel
        self.kernel = np.fft.rfft2(np.roll(padded, (-reach, -reach), axis=(0, 1)))
        self.block_i, self.block_j = block_i, block_j

    def sum_around(self, values: np.ndarray) -> np.ndarray:
        """Sum over the surroundings of every building of kernel weight x `values` (zero where unknown)."""
        grid = np.zeros(self.fft_size)
        np.add.at(grid, (self.cells[:, 0], self.cells[:, 1]), values)
        smooth = np.fft.irfft2(np.fft.rfft2(grid) * self.kernel, s=self.fft_size)
        return smooth[self.cells[:, 0], self.cells[:, 1]] - self.own * values

    def mean(self, values: np.ndarray, known: np.ndarray):
        """Weighted mean of `values` over the known buildings around each one (NaN if none), and the weight."""
        if not known.any():
            return np.full(self.count, np.nan), np.zeros(self.count)
        total = np.maximum(self.sum_around(known.astype(float)), 0.0)
        summed = self.sum_around(np.where(known, values, 0.0))
        return np.divide(summed, total, out=np.full(self.count, np.nan), where=total > 1e-6), total

    def block_mean(self, values: np.ndarray, known: np.ndarray):
        """Mean of `values` over the known buildings sharing a wall with each one (NaN if none), and their number."""
        use = known[self.block_j]
        total = np.bincount(self.block_i[use], None, self.count).astype(float)
        summed = np.bincount(self.block_i[use], values[self.block_j[use]], self.count)
        return np.divide(summed, total, out=np.full(self.count, np.nan), where=total > 0), total


def tagged_value(buildings: list[MapBuilding], name: str) -> np.ndarray:
    """The tagged value of `name` per building, NaN where the map does not give it."""
    return np.array(
        [getattr(b, name) if name in b.tagged and getattr(b, name) is not None else np.nan for b in buildings], float
    )


def _pairs_within(points: np.ndarray, distance: float):
    """(i, j, metres) for every ordered pair of distinct points closer than `distance`."""
    tree = shapely.STRtree(points)
    i, j = tree.query(points, predicate="dwithin", distance=distance)
    keep = i != j
    i, j = i[keep], j[keep]
    return i, j, shapely.distance(points[i], points[j])


def _ring_stats(n: int, i: np.ndarray, j: np.ndarray, log_area: np.ndarray):
    count = np.bincount(i, minlength=n).astype(float)
    summed = np.bincount(i, log_area[j], n)
    return count, np.divide(summed, count, out=np.full(n, np.nan), where=count > 0)


def _shared_walls(rings: np.ndarray, perimeter: np.ndarray) -> np.ndarray:
    """Share of each outline's perimeter on edges that another outline has too, between the same two
    nodes (OSM terraces share their party walls' nodes): a test on node pairs in numpy, no overlay."""
    coords, owner = shapely.get_coordinates(rings, return_index=True)
    cm = np.round(coords * 100.0).astype(np.int64)  # centimetres
    _, node = np.unique(cm[:, 0] * (1 << 32) + cm[:, 1], return_inverse=True)  # one dense id per node
    node = node.ravel().astype(np.int64)
    edge = owner[1:] == owner[:-1]  # consecutive nodes of one ring
    low, high = np.minimum(node[:-1], node[1:])[edge], np.maximum(node[:-1], node[1:])[edge]
    edge_key = low * (int(node.max()) + 1) + high
    edge_owner = owner[1:][edge]
    # Each (edge, building) once; an edge two buildings have is a party wall.
    owned = np.unique(edge_key * len(rings) + edge_owner) // len(rings)
    keys, owners = np.unique(owned, return_counts=True)
    shared = np.isin(edge_key, keys[owners > 1])
    lengths = np.hypot(*(coords[1:] - coords[:-1]).T)[edge]
    return np.minimum(np.bincount(edge_owner[shared], lengths[shared], len(rings)) / perimeter, 1.0)


def _nearest(boxes: np.ndarray, touching: np.ndarray) -> np.ndarray:
    """Metres to the nearest other building (0 where one touches, NaN beyond FAR): free-standing buildings
    are measured box to box (their oriented envelopes), which is close and far cheaper than outlines."""
    nearest = np.where(touching > 0, 0.0, np.nan)
    free = np.flatnonzero(touching == 0)
    if len(boxes) > 1 and len(free):
        (at, _), distance = shapely.STRtree(boxes).query_nearest(
            boxes[free], exclusive=True, return_distance=True, all_matches=False, max_distance=FAR
        )
        nearest[free[at]] = distance
    return nearest


def _block(n: int, block_i: np.ndarray, block_j: np.ndarray, area: np.ndarray):
    """Buildings and footprint area of the connected group of touching outlines each one belongs to."""
    graph = coo_matrix((np.ones(len(block_i)), (block_i, block_j)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    members = np.bincount(label)
    return members[label].astype(float), np.bincount(label, area)[label]


def _streets(map_data: MapData, centres: np.ndarray):
    """Rank of the nearest street within STREET_REACH of each centre and its distance (NaN where none)."""
    n = len(centres)
    rank, metres = np.full(n, np.nan), np.full(n, np.nan)
    roads = [r for r in map_data.roads if not r.tunnel]
    if not roads:
        return rank, metres
    lines = np.array([r.line for r in roads], dtype=object)
    road_rank = np.array([STREET_RANKS.get(r.kind, 0) for r in roads], float)
    points = shapely.points(centres)
    (at, road), distance = shapely.STRtree(lines).query_nearest(
        points, max_distance=STREET_REACH, return_distance=True, all_matches=False
    )
    rank[at], metres[at] = road_rank[road], distance
    return rank, metres


def _parts(buildings: list[MapBuilding], area: np.ndarray):
    """Per building: how many parts its outline has (a part: its outline's), and its share of the outline."""
    n = len(buildings)
    parent = np.array([b.parent if b.is_part and b.parent is not None else -1 for b in buildings], np.int64)
    has = parent >= 0
    counts = np.bincount(parent[has], minlength=n).astype(float)
    owner = np.where(has, parent, np.arange(n))
    share = np.where(has, area / np.maximum(area[owner], 1e-6), 1.0)
    return counts[owner], np.minimum(share, 4.0)


def urban_form(map_data: MapData) -> Form:
    """The FEATURES of every building of `map_data` (which must have at least one building)."""
    buildings = map_data.buildings
    n = len(buildings)
    outlines = np.array([b.outline for b in buildings], dtype=object)
    area = shapely.area(outlines)
    rings = shapely.get_exterior_ring(outlines)
    perimeter = np.maximum(shapely.length(rings), 1e-6)
    boxes = shapely.oriented_envelope(outlines)
    long_side, short_side, bearing = _oriented_sides(boxes, area)
    centres_geom = shapely.centroid(outlines)
    centres = shapely.get_coordinates(centres_geom)
    log_area = np.log(np.maximum(area, 1.0))

    tree = shapely.STRtree(outlines)
    bi, bj = tree.query(outlines, predicate="dwithin", distance=TOUCHING)
    keep = bi != bj
    bi, bj = bi[keep], bj[keep]
    touching = np.bincount(bi, minlength=n).astype(float)
    block_buildings, block_area = _block(n, bi, bj, area)
    nearest = _nearest(boxes, touching)

    i, j, d = _pairs_within(centres_geom, FAR)
    near = d < NEAR
    count_50, mean_50 = _ring_stats(n, i[near], j[near], log_area)
    count_100, mean_100 = _ring_stats(n, i, j, log_area)
    built_100 = (np.bincount(i, area[j], n) + area) / (np.pi * FAR**2)
    street_rank, street_m = _streets(map_data, centres)
    parts, part_share = _parts(buildings, area)

    named = forms(
        kinds=[b.kind for b in buildings],
        is_part=np.array([b.is_part for b in buildings]),
        area=area,
        short_side=short_side,
        long_side=long_side,
        block_buildings=block_buildings,
        block_area=block_area,
        parts=parts,
        part_share=part_share,
    )
    defaults = [
        FORM_DEFAULTS[f] if f in FORM_DEFAULTS and b.kind in HOUSING else defaults_for(b.kind, a, b.is_part)
        for b, a, f in zip(buildings, area, named)
    ]
    default_levels = np.array([d.levels for d in defaults], float)
    around = TaggedAround(centres, bi, bj)
    log_levels = np.log(np.maximum(tagged_value(buildings, "levels"), 1.0))
    known = np.isfinite(log_levels)
    levels_around, levels_weight = around.mean(log_levels, known)
    levels_block, block_count = around.block_mean(log_levels, known)
    heights = tagged_value(buildings, "height")
    height_block, _ = around.block_mean(np.log(np.maximum(heights, 1.0)), np.isfinite(heights))

    columns = {
        "log_area": log_area,
        "log_perimeter": np.log(perimeter),
        "compactness": 4 * np.pi * area / perimeter**2,
        "log_elongation": np.log(long_side / np.maximum(short_side, 1e-6)),
        "short_side": short_side,
        "long_side": long_side,
        "orientation_cos": np.cos(np.radians(2 * bearing)),
        "orientation_sin": np.sin(np.radians(2 * bearing)),
        "vertices": shapely.get_num_coordinates(rings) - 1.0,
        "touching": touching,
        "shared_wall_share": _shared_walls(rings, perimeter),
        "block_buildings": block_buildings,
        "log_block_area": np.log(np.maximum(block_area, 1.0)),
        "nearest_m": nearest,
        "count_50": count_50,
        "count_100": count_100,
        "mean_log_area_50": mean_50,
        "mean_log_area_100": mean_100,
        "built_share_100": built_100,
        "street_rank": street_rank,
        "street_m": street_m,
        "kind": np.array([KIND_CODES.get(b.kind, np.nan) for b in buildings], float),
        "log_default_levels": np.log(default_levels),
        "default_flat": np.array([d.roof_shape == "flat" for d in defaults], float),
        "shop": np.array([b.shop_front or "shop" in b.tags for b in buildings], float),
        "amenity": np.array(["amenity" in b.tags for b in buildings], float),
        "is_part": np.array([b.is_part for b in buildings], float),
        "parts": parts,
        "part_share": part_share,
        "levels_around": levels_around,
        "levels_around_weight": levels_weight,
        "levels_block": levels_block,
        "levels_block_count": block_count,
        "levels_around_ratio": levels_around - np.log(default_levels),
        "levels_block_ratio": levels_block - np.log(default_levels),
        "height_block": height_block,
    }
    values = np.column_stack([columns[name] for name in FEATURES]).astype(np.float64)
    return Form(values, area, short_side, long_side, bearing, default_levels, defaults, named, around)


def forms(kinds, is_part, area, short_side, long_side, block_buildings, block_area, parts, part_share) -> np.ndarray:
    """The form each building's outline and neighbours name, or "" (arrays, one value per building):

    - row_house: a housing outline standing alone, 6-12.5 m deep and at least 22 m long;
    - terrace_house: one of three or more house-sized outlines joined by party walls into a row;
    - semi_detached: one of two house-sized outlines sharing a wall;
    - shed: any outline under 30 m², or a small house-like one in a block of outbuildings;
    - tower: a compact part, a quarter of its outline or less, of a building of several parts.
    """
    kinds = np.asarray(kinds, dtype=object)
    housing = np.isin(kinds, list(HOUSING)) & ~is_part
    unit = (area >= UNIT_AREA[0]) & (area <= UNIT_AREA[1]) & (short_side <= ROW_DEPTH[1])
    alone = block_buildings <= 1
    row = housing & alone & (short_side >= ROW_DEPTH[0]) & (short_side <= ROW_DEPTH[1]) & (long_side >= ROW_LENGTH)
    mean_unit = block_area / np.maximum(block_buildings, 1.0)
    joined_units = (mean_unit >= UNIT_AREA[0]) & (mean_unit <= UNIT_AREA[1])
    terrace = housing & unit & (block_buildings >= 3) & joined_units
    semi = housing & unit & (block_buildings == 2) & joined_units
    shed = (area < SMALL_FOOTPRINT) & ~is_part
    compact = long_side <= 1.6 * np.maximum(short_side, 1e-6)
    tower = is_part & (parts >= 2) & (part_share <= TOWER_SHARE) & compact
    named = np.full(len(kinds), "", dtype=object)
    for name, where in (("tower", tower), ("semi_detached", semi), ("terrace_house", terrace), ("row_house", row)):
        named[where] = name
    named[shed] = "shed"
    return named
