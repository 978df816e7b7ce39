"""Ground laid on the terrain: triangles split until no edge is longer than a step, then raised by
the terrain's height at each corner.

Splitting always halves the longest edge at its midpoint and never touches an edge at or under the
step, so two triangles that share an edge split it at the same points whatever else they do: the
draped ground stays watertight (no T-junction opens a crack when the corners are raised).
"""

from __future__ import annotations

import numpy as np

from ._grid import Terrain

MAX_ROUNDS = 40  # halvings of one edge at most (a 1,000 km edge down to a millimetre)
# the default step, in grid cells: a chord two cells long sags a few centimetres under a smooth hill,
# far less than the BASE_DEPTH the terrain mesh lies below the ground, at a quarter of the triangles
STEP_CELLS = 2.0


def subdivided(vertices: np.ndarray, step: float) -> np.ndarray:
    """(N*3, k) triangle corners (scene x, y, z, then anything that stays with the triangle) split
    until every edge is at most `step` metres long in plan (x, z)."""
    triangles = np.asarray(vertices).reshape(-1, 3, vertices.shape[-1])
    done = []
    for _ in range(MAX_ROUNDS):
        plan = triangles[:, :, [0, 2]]
        lengths = np.linalg.norm(plan - np.roll(plan, -1, axis=1), axis=2)  # edge k runs from corner k to k + 1
        longest = lengths.argmax(axis=1)
        split = lengths[np.arange(len(triangles)), longest] > step
        done.append(triangles[~split])
        triangles = triangles[split]
        if not len(triangles):
            break
        k = longest[split]
        n = np.arange(len(triangles))
        a, b, c = triangles[n, k], triangles[n, (k + 1) % 3], triangles[n, (k + 2) % 3]
        middle = (a + b) / 2  # the trailing columns of a triangle are alike on its corners
        triangles = np.concatenate([np.stack([a, middle, c], axis=1), np.stack([middle, b, c], axis=1)])
    else:
        done.append(triangles)
    return np.concatenate(done).reshape(-1, vertices.shape[-1]).astype(vertices.dtype)


def draped(vertices: np.ndarray, terrain: Terrain, step: float | None = None) -> np.ndarray:
    """(N*3, k) scene vertices (x, y, z, ...) split to `step` (default: STEP_CELLS grid cells) and
    raised by the ground height under each: y becomes a height over the terrain."""
    if not len(vertices):
        return vertices
    out = subdivided(vertices, STEP_CELLS * terrain.spacing if step is None else step)
    out[:, 1] += terrain.scene_height_at(out[:, 0], out[:, 2]).astype(out.dtype)
    return out


def raised(points: np.ndarray, terrain: Terrain) -> np.ndarray:
    """(N, k) scene points (x, y, z, ...) with y raised by the ground height under them (no split:
    lamps, trees, lights)."""
    out = np.array(points, copy=True)
    if len(out):
        out[:, 1] += terrain.scene_height_at(out[:, 0], out[:, 2]).astype(out.dtype)
    return out
