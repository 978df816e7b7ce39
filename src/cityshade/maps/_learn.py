"""Estimates of levels, storey height and roof shape, learned from the tagged buildings of the same map.

Levels: a ridge regression of log(levels / type default) on the outline's size and shape, how built-up
the surroundings are, and what the tagged buildings around say (distance-weighted, within RADIUS, and
separately those that share a wall: the block). Training uses the map's own tagged buildings, each
described without itself, exactly as an untagged building is. With few tagged buildings the ridge
penalty keeps the estimate near the regional default; with none it is the default.

Height: where tagged buildings share a wall with it (the block), their height; else levels x storey.
Storey height: the mean of tagged height / levels per type, shrunk toward the regional default.
Roof shape: a vote of the tagged roofs nearby (closer counts more), on top of the map's own mix per
building type and the regional default as a prior.

Everything is vectorised (shapely STRtree bulk queries, numpy), so 100,000 buildings take seconds.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
import shapely

from ._defaults import SMALL_FOOTPRINT, defaults_for
from ._model import ROOF_SHAPES, MapBuilding

RADIUS = 250.0  # metres: tagged buildings this close inform a guess
HALF_WEIGHT = 120.0  # metres at which a neighbour's weight halves
TOUCHING = 1.0  # metres: outlines this close share a wall (the same block)
DENSITY_CELL = 100.0  # metres: the grid on which built-up share is measured
RIDGE = 8.0  # penalty on the regression weights, in units of training buildings
PRIOR_VOTES = 3.0  # the regional default roof counts as this many tagged neighbours
STOREY_PRIOR = 4.0  # the regional storey height counts as this many tagged buildings


@dataclass
class Estimates:
    levels: np.ndarray  # storeys below the roof
    storey: np.ndarray  # metres floor to floor
    roof_shape: np.ndarray  # object array of ROOF_SHAPES values
    block_height: np.ndarray  # tagged height of the buildings sharing a wall (distance-weighted), NaN if none


def estimate(buildings: list[MapBuilding], shape) -> Estimates:
    """Estimates for every building (tagged ones too: the caller keeps tagged values)."""
    kinds = [b.kind for b in buildings]
    defaults = [defaults_for(b.kind, a, b.is_part) for b, a in zip(buildings, shape.area)]
    default_levels = np.array([d.levels for d in defaults], float)
    centres = shapely.get_coordinates(shapely.centroid(np.array([b.outline for b in buildings], dtype=object)))
    neighbours = _Neighbours(buildings, centres)
    levels = _levels(buildings, shape, centres, default_levels, neighbours)
    parts = np.array([b.is_part for b in buildings])
    levels[((shape.area < SMALL_FOOTPRINT) & ~parts) | np.array([d.small for d in defaults])] = 1.0
    storey = _storeys(buildings, kinds, np.array([d.storey for d in defaults], float))
    roofs = _roof_shapes(buildings, kinds, defaults, neighbours)
    heights = np.array([b.height if "height" in b.tagged and b.height is not None else 0.0 for b in buildings], float)
    block_height, weight = neighbours.mean(heights, heights > 0, neighbours.touching)
    return Estimates(levels, storey, roofs, np.where(weight > 0, block_height, np.nan))


class _Neighbours:
    """Pairs (building, other building) within RADIUS, with distance weights, from one bulk query."""

    def __init__(self, buildings: list[MapBuilding], centres: np.ndarray):
        outlines = np.array([b.outline for b in buildings], dtype=object)
        tree = shapely.STRtree(outlines)
        i, j = tree.query(outlines, predicate="dwithin", distance=RADIUS)
        keep = i != j
        self.i, self.j = i[keep], j[keep]
        self.gap = shapely.distance(outlines[self.i], outlines[self.j])
        self.weight = 1.0 / (1.0 + (np.hypot(*(centres[self.i] - centres[self.j]).T) / HALF_WEIGHT) ** 2)
        self.touching = self.gap <= TOUCHING
        self.count = len(buildings)

    def mean(self, values: np.ndarray, known: np.ndarray, pairs: np.ndarray | None = None):
        """Weighted mean of `values` over the known neighbours of each building, and the weight summed."""
        use = known[self.j] if pairs is None else known[self.j] & pairs
        w = self.weight[use]
        total = np.bincount(self.i[use], w, self.count)
        summed = np.bincount(self.i[use], w * values[self.j[use]], self.count)
        return np.divide(summed, total, out=np.zeros(self.count), where=total > 0), total


def _density(shape, centres: np.ndarray) -> np.ndarray:
    """Share of the ground covered by footprints in the 3x3 cells around each building."""
    cells = np.floor((centres - centres.min(axis=0)) / DENSITY_CELL).astype(np.int64) + 1
    grid = np.zeros(tuple(cells.max(axis=0) + 2))
    np.add.at(grid, (cells[:, 0], cells[:, 1]), shape.area)
    padded = np.pad(grid, 1)
    around = sum(padded[1 + dx:padded.shape[0] - 1 + dx, 1 + dy:padded.shape[1] - 1 + dy]
                 for dx in (-1, 0, 1) for dy in (-1, 0, 1))
    return np.minimum(around[cells[:, 0], cells[:, 1]] / (9 * DENSITY_CELL**2), 1.0)


def _levels(buildings, shape, centres, default_levels, neighbours: _Neighbours) -> np.ndarray:
    tagged = np.array([b.levels is not None and "levels" in b.tagged for b in buildings])
    if tagged.sum() < 2:
        return default_levels.copy()
    known_levels = np.array([b.levels if t else 1.0 for b, t in zip(buildings, tagged)], float)
    residual = np.log(np.maximum(known_levels, 1.0) / default_levels)
    typical = residual[tagged].mean()
    around, around_weight = neighbours.mean(residual, tagged)
    block, block_weight = neighbours.mean(residual, tagged, neighbours.touching)
    around = np.where(around_weight > 0, around, typical)
    features = np.column_stack([
        around,
        np.where(block_weight > 0, block, around),  # the block first, the surroundings where it has no tag
        block_weight > 0,
        np.log(np.maximum(shape.area, 1.0)),
        shape.compactness,
        np.log(shape.elongation),
        _density(shape, centres),
        np.array([b.is_part for b in buildings], float),
        np.log(default_levels),
    ])
    train = features[tagged]
    mean, scale = train.mean(axis=0), train.std(axis=0) + 1e-9
    x = (features - mean) / scale
    xt, yt = x[tagged], residual[tagged]
    weights = np.linalg.solve(xt.T @ xt + RIDGE * np.eye(x.shape[1]), xt.T @ (yt - typical))
    # Few tagged buildings: the map's typical departure from the defaults is shrunk toward none.
    bias = typical * tagged.sum() / (tagged.sum() + RIDGE)
    return np.clip(np.round(default_levels * np.exp(x @ weights + bias)), 1.0, 80.0)


def _storeys(buildings, kinds, default_storey) -> np.ndarray:
    """Per type: (prior * default + sum of tagged storey heights) / (prior + count)."""
    sums, counts = Counter(), Counter()
    for b in buildings:
        if {"height", "levels"} <= b.tagged and b.levels > (b.min_level or 0):
            walls = b.height - (b.roof_height or 0.0) - (b.min_height or 0.0)
            storey = walls / (b.levels - (b.min_level or 0.0))
            if 2.2 <= storey <= 8.0:
                sums[b.kind] += storey
                counts[b.kind] += 1
    learned = [(STOREY_PRIOR * d + sums[k]) / (STOREY_PRIOR + counts[k]) for k, d in zip(kinds, default_storey)]
    return np.array(learned, float)


def _roof_shapes(buildings, kinds, defaults, neighbours: _Neighbours) -> np.ndarray:
    shapes = np.array([b.roof_shape if "roof_shape" in b.tagged and b.roof_shape in ROOF_SHAPES else "" for b in buildings],
                      dtype=object)
    known = shapes != ""
    votes = np.zeros((len(buildings), len(ROOF_SHAPES)))
    code = {s: n for n, s in enumerate(ROOF_SHAPES)}
    # The map's own mix per building type, then the regional default, as the prior.
    mix = Counter((k, s) for k, s, t in zip(kinds, shapes, known) if t)
    per_kind = Counter(k for k, t in zip(kinds, known) if t)
    for n, (kind, d) in enumerate(zip(kinds, defaults)):
        votes[n, code[d.roof_shape]] += PRIOR_VOTES
        if per_kind[kind]:
            for s, c in enumerate(ROOF_SHAPES):
                votes[n, s] += PRIOR_VOTES * mix[(kind, c)] / per_kind[kind]
    use = known[neighbours.j]
    codes = np.array([code.get(s, 0) for s in shapes])
    np.add.at(votes, (neighbours.i[use], codes[neighbours.j[use]]), neighbours.weight[use] * 4.0)
    return np.array(ROOF_SHAPES, dtype=object)[votes.argmax(axis=1)]
