"""Estimates of levels, storey height and roof shape, learned from the tagged buildings of the same map.

Levels: a ridge regression of log(levels / type default) on the outline's size and shape, how built-up
the surroundings are, and what the tagged buildings around say (distance-weighted, within RADIUS, and
separately those that share a wall: the block). Training uses the map's own tagged buildings, each
described without itself, exactly as an untagged building is. With few tagged buildings the ridge
penalty keeps the estimate near the regional default; with none it is the default.

Height: where tagged buildings share a wall with it (the block), their height; else levels x storey.
Storey height: the mean of tagged height / levels per type, shrunk toward the regional default.
Roof shape: a vote of the tagged roofs nearby (closer counts more; domes, onions, cones, round and
pyramidal roofs only among the parts of one building and buildings of the same named type), on top of the map's own mix per building type
and the regional default as a prior.

Everything is vectorised (shapely STRtree bulk queries, numpy), so 100,000 buildings take seconds.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
import shapely

from ._defaults import GENERIC, SMALL_FOOTPRINT, defaults_for
from ._model import ROOF_SHAPES, MapBuilding

RADIUS = 250.0  # metres: tagged buildings this close inform a guess
HALF_WEIGHT = 120.0  # metres at which a neighbour's weight halves
TOUCHING = 1.0  # metres: outlines this close share a wall (the same block)
CELL = 20.0  # metres: the grid on which the surroundings are summed
MAX_GRID = 3072  # cells a side at most: wider extracts (over 61 km) are summed on a coarser grid
DENSITY_CELL = 100.0  # metres: the grid on which built-up share is measured
RIDGE = 8.0  # penalty on the regression weights, in units of training buildings
LANDMARK_ROOFS = {"dome", "onion", "round", "cone", "pyramidal"}  # not spread to the buildings around
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
    block_height, weight = neighbours.block_mean(heights, heights > 0)
    return Estimates(levels, storey, roofs, np.where(weight > 0, block_height, np.nan))


class _Neighbours:
    """Distance-weighted sums over the tagged buildings around each building, the building itself left out.

    The surroundings (within RADIUS) are summed on a CELL grid by one FFT convolution per quantity, so the
    cost does not grow with how many tagged buildings stand near each other; the block (outlines within
    TOUCHING) comes from one bulk STRtree query.
    """

    def __init__(self, buildings: list[MapBuilding], centres: np.ndarray):
        self.count = len(buildings)
        extent = float(np.ptp(centres, axis=0).max()) if len(centres) else 0.0
        cell = max(CELL, extent / MAX_GRID)  # bounded memory however far apart the buildings are
        reach = int(np.ceil(RADIUS / cell))
        self.cells = np.floor((centres - centres.min(axis=0)) / cell).astype(np.int64) + reach
        self.shape = tuple(self.cells.max(axis=0) + reach + 1)
        d = np.hypot(*np.meshgrid(np.arange(-reach, reach + 1), np.arange(-reach, reach + 1), indexing="ij")) * cell
        kernel = np.where(d <= RADIUS, 1.0 / (1.0 + (d / HALF_WEIGHT) ** 2), 0.0)
        self.own = kernel[reach, reach]
        size = tuple(n + 2 * reach for n in self.shape)
        padded = np.zeros(size)
        padded[: kernel.shape[0], : kernel.shape[1]] = kernel
        self.kernel = np.fft.rfft2(np.roll(padded, (-reach, -reach), axis=(0, 1)))
        self.fft_size = size
        outlines = np.array([b.outline for b in buildings], dtype=object)
        i, j = shapely.STRtree(outlines).query(outlines, predicate="dwithin", distance=TOUCHING)
        self.block_i, self.block_j = i[i != j], j[i != j]

    def sum_around(self, values: np.ndarray) -> np.ndarray:
        """Sum over the surroundings of every building of kernel weight x `values` (zero where unknown)."""
        grid = np.zeros(self.fft_size)
        np.add.at(grid, (self.cells[:, 0], self.cells[:, 1]), values)
        smooth = np.fft.irfft2(np.fft.rfft2(grid) * self.kernel, s=self.fft_size)
        return smooth[self.cells[:, 0], self.cells[:, 1]] - self.own * values

    def mean(self, values: np.ndarray, known: np.ndarray):
        """Weighted mean of `values` over the known buildings around each one, and the weight summed."""
        total = np.maximum(self.sum_around(known.astype(float)), 0.0)
        summed = self.sum_around(np.where(known, values, 0.0))
        return np.divide(summed, total, out=np.zeros(self.count), where=total > 1e-6), total

    def block_mean(self, values: np.ndarray, known: np.ndarray):
        """Mean of `values` over the known buildings sharing a wall with each one, and their number."""
        use = known[self.block_j]
        total = np.bincount(self.block_i[use], None, self.count).astype(float)
        summed = np.bincount(self.block_i[use], values[self.block_j[use]], self.count)
        return np.divide(summed, total, out=np.zeros(self.count), where=total > 0), total


def _density(shape, centres: np.ndarray) -> np.ndarray:
    """Share of the ground covered by footprints in the 3x3 cells around each building. Only occupied
    cells are kept (sorted keys), so buildings far apart cost no memory between them."""
    cells = np.floor((centres - centres.min(axis=0)) / DENSITY_CELL).astype(np.int64) + 1
    width = int(cells[:, 1].max()) + 2
    keys, inverse = np.unique(cells[:, 0] * width + cells[:, 1], return_inverse=True)
    covered = np.bincount(inverse.ravel(), shape.area, len(keys))
    around = np.zeros(len(cells))
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            wanted = (cells[:, 0] + dx) * width + cells[:, 1] + dy
            at = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
            around += np.where(keys[at] == wanted, covered[at], 0.0)
    return np.minimum(around / (9 * DENSITY_CELL**2), 1.0)


def _levels(buildings, shape, centres, default_levels, neighbours: _Neighbours) -> np.ndarray:
    tagged = np.array([b.levels is not None and "levels" in b.tagged for b in buildings])
    if tagged.sum() < 2:
        return default_levels.copy()
    known_levels = np.array([b.levels if t else 1.0 for b, t in zip(buildings, tagged)], float)
    residual = np.log(np.maximum(known_levels, 1.0) / default_levels)
    typical = residual[tagged].mean()
    around, around_weight = neighbours.mean(residual, tagged)
    block, block_weight = neighbours.block_mean(residual, tagged)
    around = np.where(around_weight > 0, around, typical)
    features = np.column_stack(
        [
            around,
            np.where(block_weight > 0, block, around),  # the block first, the surroundings where it has no tag
            block_weight > 0,
            np.log(np.maximum(shape.area, 1.0)),
            shape.compactness,
            np.log(shape.elongation),
            _density(shape, centres),
            np.array([b.is_part for b in buildings], float),
            np.log(default_levels),
        ]
    )
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
    shapes = np.array(
        [b.roof_shape if "roof_shape" in b.tagged and b.roof_shape in ROOF_SHAPES else "" for b in buildings],
        dtype=object,
    )
    known = shapes != ""
    code = {s: n for n, s in enumerate(ROOF_SHAPES)}
    # The prior: the regional default, plus the map's own mix of roofs for the building's type.
    votes = np.zeros((len(buildings), len(ROOF_SHAPES)))
    votes[np.arange(len(buildings)), [code[d.roof_shape] for d in defaults]] = PRIOR_VOTES
    names, kind_index = np.unique(np.array(kinds, dtype=object), return_inverse=True)
    mix = np.zeros((len(names), len(ROOF_SHAPES)))
    np.add.at(mix, (kind_index[known], [code[s] for s in shapes[known]]), 1.0)
    votes += PRIOR_VOTES * mix[kind_index] / np.maximum(mix.sum(axis=1, keepdims=True), 1.0)[kind_index]
    kinds = np.array(kinds, dtype=object)
    for shape in sorted(set(shapes[known])):
        if shape not in LANDMARK_ROOFS:
            votes[:, code[shape]] += 4.0 * neighbours.sum_around((shapes == shape).astype(float))
            continue
        # A dome belongs to its building: the parts it shares a wall with, and nearby buildings of the
        # same named type (the chapels of one monastery), take it; ordinary buildings around do not.
        votes[:, code[shape]] += 4.0 * neighbours.block_mean(np.ones(len(buildings)), shapes == shape)[1]
        for kind in sorted(set(kinds[shapes == shape]) - GENERIC):
            same = kinds == kind
            votes[same, code[shape]] += 4.0 * neighbours.sum_around(((shapes == shape) & same).astype(float))[same]
    return np.array(ROOF_SHAPES, dtype=object)[votes.argmax(axis=1)]
