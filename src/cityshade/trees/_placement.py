"""Where trees stand: instance records for single trees, park groves and street rows."""

from __future__ import annotations

import numpy as np

from ._species import SPECIES

SPECIES_ORDER = tuple(SPECIES)  # species index in instance records
TREE_DTYPE = np.dtype([
    ("position", "3f4"), ("yaw", "f4"), ("scale", "f4"), ("phase", "f4"), ("species", "i4"),
])


def tree_instances(positions, species, rng: np.random.Generator) -> np.ndarray:
    """Records for trees at the given (x, y, z) positions with random yaw, size and wind phase."""
    positions = np.asarray(positions, float).reshape(-1, 3)
    trees = np.zeros(len(positions), TREE_DTYPE)
    trees["position"] = positions
    trees["yaw"] = rng.uniform(0, 2 * np.pi, len(trees))
    trees["scale"] = rng.uniform(0.85, 1.15, len(trees))
    trees["phase"] = rng.uniform(0, 2 * np.pi, len(trees))
    names = [species] * len(trees) if isinstance(species, str) else list(species)
    trees["species"] = [SPECIES_ORDER.index(n) for n in names]
    return trees


def park_trees(rect, seed: int, spacing: float = 9.0) -> np.ndarray:
    """A grove filling a rectangle (x0, z0, x1, z1): jittered grid, mixed species, a clearing in the middle."""
    rng = np.random.default_rng(seed)
    x0, z0, x1, z1 = rect
    xs = np.arange(x0 + spacing / 2, x1 - spacing / 4, spacing)
    zs = np.arange(z0 + spacing / 2, z1 - spacing / 4, spacing)
    grid = np.array([(x, z) for x in xs for z in zs]) + rng.uniform(-0.3, 0.3, (len(xs) * len(zs), 2)) * spacing
    centre = np.array([(x0 + x1) / 2, (z0 + z1) / 2])
    keep = np.linalg.norm((grid - centre) / (np.array([x1 - x0, z1 - z0]) / 2), axis=1) > 0.45
    grid = grid[keep]
    positions = np.column_stack([grid[:, 0], np.zeros(len(grid)), grid[:, 1]])
    species = rng.choice(SPECIES_ORDER, size=len(grid), p=(0.5, 0.3, 0.2))
    return tree_instances(positions, species, rng)


def street_trees(streets, seed: int, spacing: float = 14.0, inset: float = 1.2, species: str = "poplar") -> np.ndarray:
    """A row of trees along both kerbs of each street rectangle (x0, z0, x1, z1), on its long axis."""
    rng = np.random.default_rng(seed)
    positions = []
    for x0, z0, x1, z1 in streets:
        along_x = (x1 - x0) >= (z1 - z0)
        length = (x1 - x0) if along_x else (z1 - z0)
        steps = np.arange(spacing / 2, length, spacing)
        for edge in ((z0 - inset, z1 + inset) if along_x else (x0 - inset, x1 + inset)):
            for s in steps:
                positions.append((x0 + s, 0.0, edge) if along_x else (edge, 0.0, z0 + s))
    return tree_instances(positions, species, rng)
