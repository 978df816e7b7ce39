"""A city's trees bucketed in square cells of the ground, so that the tree pass's per-tree work
each frame and shadow cascade (distance, fade, frustum test, trees/_tree_pass.py) touches only the
trees of cells that can hold one it draws: from the street, most of a city's trees are outside
the view or too far to span a pixel."""

from __future__ import annotations

import numpy as np

from ..frame import frustum_planes

CELL_METRES = 64.0
MARGIN_METRES = 1.0  # the cell tests are conservative by this much beyond rounding


class TreeCells:
    def __init__(self, positions: np.ndarray, heights: np.ndarray, cell: float = CELL_METRES):
        """`positions` (N, 3) and `heights` (N,) of the trees, as the tree pass tests them."""
        keys = np.floor(positions[:, [0, 2]] / cell).astype(np.int64)
        _, cell_of = np.unique(keys, axis=0, return_inverse=True)
        cell_of = cell_of.reshape(-1).astype(np.int32)  # a city's trees: 4 bytes each, not 8
        count = int(cell_of.max()) + 1 if len(cell_of) else 0
        self.cell_of = cell_of
        self.lo = np.full((count, 3), np.inf)
        self.hi = np.full((count, 3), -np.inf)
        np.minimum.at(self.lo, cell_of, positions)
        np.maximum.at(self.hi, cell_of, positions)
        self.height = np.zeros(count)
        np.maximum.at(self.height, cell_of, heights)

    def candidates(self, eye, view_projection=None, sway: float = 0.0, focal_rows=None, vanish_rows=0.0):
        """Indices (ascending) of every tree in a cell that may hold one inside the frustum of
        `view_projection` (boxes reaching the tallest tree's height plus `sway`), and, with
        `focal_rows`, one whose height spans more than `vanish_rows` image rows from `eye`."""
        keep = np.ones(len(self.lo), bool)
        if focal_rows is not None:
            nearest = np.clip(np.asarray(eye, float), self.lo, self.hi)
            distance = np.linalg.norm(nearest - np.asarray(eye, float), axis=1) - MARGIN_METRES
            keep &= self.height * focal_rows > vanish_rows * np.maximum(distance, 0.0)
        if view_projection is not None:
            centre, half = (self.lo + self.hi) / 2, (self.hi - self.lo) / 2 + (self.height + sway)[:, None]
            for a, b, c, d in frustum_planes(view_projection):
                reach = abs(a) * half[:, 0] + abs(b) * half[:, 1] + abs(c) * half[:, 2]
                keep &= a * centre[:, 0] + b * centre[:, 1] + c * centre[:, 2] + d + reach >= -MARGIN_METRES
        return np.flatnonzero(keep[self.cell_of])
