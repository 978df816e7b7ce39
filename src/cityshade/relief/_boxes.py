"""The free-box acceleration structure A (paper §4.2).

For a texel t of depth d, a box of free space is a rectangle of texels none of which is higher
(smaller depth) than d: a ray inside it above depth d cannot hit anything. The box is grown
greedily from t, one texel per round in the four directions (left, right, down, up, in that
order) until no direction can grow; every unassigned texel of the same depth inside the box
shares it. A stores one box index per texel; the boxes are half-open texel rectangles
(x0, y0, x1, y1) in facade coordinates.

Growing one texel at a time would take thousands of rounds per box on a 2048-texel facade.
Rows (columns) that repeat their predecessor form runs, and a round's outcome can only change
when an edge enters a new run, so the rounds in between are taken in one jump; the result is
the same box as the texel-by-texel growth.
"""

from __future__ import annotations

import numpy as np


def _run_starts(depth: np.ndarray, axis: int) -> np.ndarray:
    """starts[i] is True where line i differs from line i-1 along axis; True at 0 and at the end."""
    lines = depth if axis == 0 else depth.T
    starts = np.ones(lines.shape[0] + 1, bool)
    starts[1:-1] = (lines[1:] != lines[:-1]).any(axis=1)
    return starts


def _previous_start(starts: np.ndarray) -> np.ndarray:
    """For each i, the largest j <= i with starts[j]."""
    idx = np.where(starts, np.arange(starts.size), 0)
    return np.maximum.accumulate(idx)


def _next_start(starts: np.ndarray) -> np.ndarray:
    """For each i, the smallest j >= i with starts[j]."""
    idx = np.where(starts, np.arange(starts.size), starts.size - 1)
    return np.minimum.accumulate(idx[::-1])[::-1]


def free_boxes(depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A (rows, cols) uint32 box index per texel and the boxes (n, 4) uint16 as x0, y0, x1, y1."""
    rows, cols = depth.shape
    col_starts, row_starts = _run_starts(depth, 1), _run_starts(depth, 0)
    col_prev, col_next = _previous_start(col_starts), _next_start(col_starts)
    row_prev, row_next = _previous_start(row_starts), _next_start(row_starts)

    index = np.full(rows * cols, -1, np.int64)
    flat_depth = depth.reshape(-1)
    boxes: list[tuple[int, int, int, int]] = []
    cursor = 0
    while True:
        unassigned = index[cursor:] < 0
        if not unassigned.any():
            break
        cursor += int(np.argmax(unassigned))
        r, c = divmod(cursor, cols)
        d = flat_depth[cursor]
        x0, y0, x1, y1 = _grow(depth, d, c, r, col_prev, col_next, row_prev, row_next)
        block = index.reshape(rows, cols)[y0:y1, x0:x1]
        block[(block < 0) & (depth[y0:y1, x0:x1] == d)] = len(boxes)
        boxes.append((x0, y0, x1, y1))
    return index.reshape(rows, cols).astype(np.uint32), np.array(boxes, np.uint16).reshape(-1, 4)


def _grow(depth, d, c, r, col_prev, col_next, row_prev, row_next):
    rows, cols = depth.shape
    x0, x1, y0, y1 = c, c + 1, r, r + 1
    left = right = down = up = True
    while left or right or down or up:
        # Rounds before any active edge enters a new run all succeed: take them at once.
        # Entering column x0-1 crosses a run boundary when column x0 starts a run, etc.
        steps = []
        if left:
            steps.append(x0 - col_prev[x0] + 1)
        if right:
            steps.append(col_next[x1] - x1 + 1)
        if down:
            steps.append(y0 - row_prev[y0] + 1)
        if up:
            steps.append(row_next[y1] - y1 + 1)
        jump = min(steps) - 1
        if jump > 0:
            x0 -= jump * left
            x1 += jump * right
            y0 -= jump * down
            y1 += jump * up
        # One round checked texel by texel.
        if left:
            left = x0 > 0 and depth[y0:y1, x0 - 1].min() >= d
            x0 -= left
        if right:
            right = x1 < cols and depth[y0:y1, x1].min() >= d
            x1 += right
        if down:
            down = y0 > 0 and depth[y0 - 1, x0:x1].min() >= d
            y0 -= down
        if up:
            up = y1 < rows and depth[y1, x0:x1].min() >= d
            y1 += up
    return int(x0), int(y0), int(x1), int(y1)
