"""Where trees stand: instance records for single trees, park groves and street rows."""

from __future__ import annotations

import numpy as np

from ._species import SPECIES

SPECIES_ORDER = tuple(SPECIES)  # species index in instance records
TREE_DTYPE = np.dtype(
    [
        ("position", "3f4"),
        ("yaw", "f4"),
        ("scale", "f4"),
        ("phase", "f4"),
        ("species", "i4"),
    ]
)


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
    species = rng.choice(SPECIES_ORDER, size=len(grid), p=(0.5, 0.3, 0.2, 0.0))  # no pines in the generator's parks
    return tree_instances(positions, species, rng)


def street_trees(streets, seed: int, spacing: float = 18.0, inset: float = 1.2, species: str = "poplar") -> np.ndarray:
    """Rows of trees on the pavement strips along both kerbs of each street rectangle (x0, z0, x1,
    z1), `inset` metres in from its edges, skipping the crossings with the other streets."""
    rng = np.random.default_rng(seed)
    rects = np.asarray(streets, float).reshape(-1, 4)
    positions = []
    for index, (x0, z0, x1, z1) in enumerate(rects):
        along_x = (x1 - x0) >= (z1 - z0)
        start, end = (x0, x1) if along_x else (z0, z1)
        s = np.arange(start + spacing / 2, end, spacing)
        edges = (z0 + inset, z1 - inset) if along_x else (x0 + inset, x1 - inset)
        row = np.stack([np.broadcast_to(e, s.shape) for e in edges], axis=1)  # (spots, both kerbs)
        s = np.broadcast_to(s[:, None], row.shape)
        x, z = (s, row) if along_x else (row, s)
        x, z = x.ravel(), z.ravel()  # spot by spot, both kerbs each
        others = np.delete(rects, index, axis=0)[:, None]
        crossing = (
            (others[..., 0] - 4 < x) & (x < others[..., 2] + 4) & (others[..., 1] - 4 < z) & (z < others[..., 3] + 4)
        )
        free = ~crossing.any(axis=0)
        positions.append(np.column_stack([x[free], np.zeros(int(free.sum())), z[free]]))
    return tree_instances(np.concatenate(positions) if positions else np.zeros((0, 3)), species, rng)


def city_trees(city, seed: int | None = None) -> np.ndarray:
    """The trees of a city: groves filling its parks and rows along its streets."""
    seed = city.seed if seed is None else seed
    groups = [park_trees(rect, seed + k) for k, rect in enumerate(city.parks)]
    if city.streets:
        groups.append(street_trees(city.streets, seed))
    return np.concatenate(groups) if groups else np.zeros(0, TREE_DTYPE)
