"""Procedural trees: a recursive parametric branching skeleton, meshed at two levels of detail.

The skeleton (branch centre lines and radii) is drawn once from the seed; each LOD meshes the
same skeleton, so the two LODs of a tree line up during a cross-fade. Branches are generalised
cylinders with UVs, tangents and smooth radial normals (the silhouette fins need smooth
per-vertex normals, §4.2.1). The last branching level carries leaf cards (§4.3.1) and, for
conifers, frond ribbons.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._species import Species

# Interleaved float32 vertex layouts; the names match the shader inputs.
BRANCH_LAYOUT = "3f 3f 3f 2f 1f 1f"
BRANCH_ATTRIBUTES = ("in_position", "in_normal", "in_tangent", "in_uv", "in_radius", "in_wind")
CARD_LAYOUT = "3f 2f 1f 1f 1f 1f"
CARD_ATTRIBUTES = ("in_center", "in_corner", "in_size", "in_cell", "in_wind", "in_spin")
FROND_LAYOUT = "3f 3f 2f 1f"
FROND_ATTRIBUTES = ("in_position", "in_normal", "in_uv", "in_wind")
BRANCH_FLOOR = 0.4  # metres: the lowest a branch's axis may sink, so its bark and needles stay above the ground

LOD_DETAIL = (
    # radial segments, segments per metre, share of leaf cards kept, card size scale
    (10, 2.0, 1.0, 1.0),
    (5, 0.8, 0.5, 1.35),
)


@dataclass
class Branch:
    points: np.ndarray  # (n, 3) centre line
    radii: np.ndarray  # (n,)
    wind: np.ndarray  # (n,) sway weight
    level: int


@dataclass
class TreeMesh:
    """One LOD of one tree in model space (metres, y up, trunk base at the origin)."""

    branches: np.ndarray  # (n, 13) float32, BRANCH_LAYOUT
    branch_indices: np.ndarray  # (m,) uint32 triangles
    cards: np.ndarray  # (4k, 9) float32, CARD_LAYOUT
    card_indices: np.ndarray
    fronds: np.ndarray  # (n, 9) float32, FROND_LAYOUT
    frond_indices: np.ndarray


@dataclass
class TreeModel:
    species: Species
    seed: int
    lods: list[TreeMesh] = field(default_factory=list)
    height: float = 0.0
    crown_radius: float = 0.0


def _perpendicular(v: np.ndarray) -> np.ndarray:
    a = np.array([1.0, 0.0, 0.0]) if abs(v[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    p = np.cross(v, a)
    return p / np.linalg.norm(p)


def _rotate(v: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues rotation of v about a unit axis."""
    return v * np.cos(angle) + np.cross(axis, v) * np.sin(angle) + axis * np.dot(axis, v) * (1 - np.cos(angle))


def _grow(start, direction, length, radius, level, species, rng, wind0) -> Branch:
    segments = max(4, int(length * 3))
    step = length / segments
    points, d = [np.asarray(start, float)], np.asarray(direction, float)
    for _ in range(segments):
        d = _rotate(d, _perpendicular(d), rng.normal(0, species.gnarl * (0.3 if level == 0 else 1.0)))
        if level > 0:  # the trunk stays upright; branches bend up or droop
            d = d + np.array([0.0, species.tropism * step * 4, 0.0])
            if points[-1][1] + d[1] * step < BRANCH_FLOOR:  # a drooping branch runs along the ground, not into it
                d[1] = max(d[1], 0.0)
        d /= np.linalg.norm(d)
        points.append(points[-1] + d * step)
    s = np.linspace(0.0, 1.0, segments + 1)
    radii = radius * (1.0 - 0.75 * s)
    wind = wind0 + s * (0.15 + 0.25 * level)
    return Branch(np.array(points), radii, wind, level)


def _sample(branch: Branch, t: float):
    """Point, direction, radius and wind at fraction t along a branch."""
    n = len(branch.points) - 1
    i = min(int(t * n), n - 1)
    f = t * n - i
    p = branch.points[i] * (1 - f) + branch.points[i + 1] * f
    d = branch.points[i + 1] - branch.points[i]
    r = branch.radii[i] * (1 - f) + branch.radii[i + 1] * f
    w = branch.wind[i] * (1 - f) + branch.wind[i + 1] * f
    return p, d / np.linalg.norm(d), r, w


def skeleton(species: Species, seed: int) -> list[Branch]:
    """All branches, trunk first; deterministic for (species, seed)."""
    rng = np.random.default_rng(seed)
    trunk = _grow((0, 0, 0), (0, 1, 0), species.trunk_length, species.trunk_radius, 0, species, rng, 0.0)
    trunk.wind[:] = 0.12 * np.linspace(0, 1, len(trunk.wind)) ** 2
    branches, parents = [trunk], [trunk]
    parent_length = species.trunk_length
    golden = np.pi * (3 - np.sqrt(5))
    for level, count in enumerate(species.children):
        children = []
        for parent in parents:
            azimuth = rng.uniform(0, 2 * np.pi)
            for k in range(count):
                t = species.branch_start + (1 - species.branch_start) * (k + rng.uniform(0.2, 0.8)) / count
                p, d, r, w = _sample(parent, min(t, 0.98))
                azimuth += golden + rng.normal(0, 0.2)
                side = _rotate(_perpendicular(d), d, azimuth)
                spread = species.spread[level] + rng.normal(0, 0.1)
                child_dir = _rotate(d, np.cross(d, side) / np.linalg.norm(np.cross(d, side)), spread)
                shape = 1 - species.cone * (t - species.branch_start) / (1 - species.branch_start)
                length = parent_length * species.length_ratio[level] * max(shape, 0.15) * rng.uniform(0.8, 1.15)
                children.append(_grow(p, child_dir, length, max(r * 0.6, 0.015), level + 1, species, rng, w))
        branches += children
        parents = children
        parent_length *= species.length_ratio[level]
    return branches


def _transport_frames(points: np.ndarray):
    """Tangents and parallel-transported normals along a polyline (no twist)."""
    t = np.gradient(points, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    normals = [_perpendicular(t[0])]
    for i in range(1, len(t)):
        n = normals[-1] - t[i] * np.dot(normals[-1], t[i])
        normals.append(n / np.linalg.norm(n))
    return t, np.array(normals)


def _mesh_branch(branch: Branch, species: Species, radial: int, per_metre: float):
    length = np.sum(np.linalg.norm(np.diff(branch.points, axis=0), axis=1))
    rings = max(2, int(np.ceil(length * per_metre)) + 1)
    ts = np.linspace(0, 1, rings)
    samples = [_sample(branch, min(t, 1 - 1e-6)) for t in ts]
    centres = np.array([s[0] for s in samples])
    radii = np.array([s[2] for s in samples])
    winds = np.array([s[3] for s in samples])
    axis, normal0 = _transport_frames(centres)
    binormal0 = np.cross(axis, normal0)
    # u repeats a whole number of times around the circumference so texels stay square.
    u_repeats = max(1, round(2 * np.pi * radii[0] / species.bark_tile))
    angle = np.linspace(0, 2 * np.pi, radial + 1)
    cos, sin = np.cos(angle)[None, :, None], np.sin(angle)[None, :, None]
    normals = cos * normal0[:, None] + sin * binormal0[:, None]  # (rings, radial+1, 3)
    tangents = -sin * normal0[:, None] + cos * binormal0[:, None]
    positions = centres[:, None] + normals * radii[:, None, None]
    v = ts * length / species.bark_tile
    uv = np.stack(np.broadcast_arrays((angle / (2 * np.pi) * u_repeats)[None, :], v[:, None]), axis=-1)
    verts = np.concatenate(
        [
            positions,
            normals,
            tangents,
            uv,
            np.broadcast_to(radii[:, None, None], (rings, radial + 1, 1)),
            np.broadcast_to(winds[:, None, None], (rings, radial + 1, 1)),
        ],
        axis=-1,
    ).reshape(-1, 13)
    i, j = np.meshgrid(np.arange(rings - 1), np.arange(radial), indexing="ij")
    a = i * (radial + 1) + j
    b, c, d = a + 1, a + radial + 1, a + radial + 2
    quads = np.stack([a, b, c, b, d, c], axis=-1).reshape(-1)  # counter-clockwise seen from outside
    return verts, quads


def _leaf_cards(leaf_branches, species: Species, rng, keep: float, scale: float):
    cards = []
    for branch in leaf_branches:
        for _ in range(species.leaves_per_branch):
            if rng.uniform() > keep:
                continue
            p, d, r, w = _sample(branch, rng.uniform(0.3, 0.999))
            offset = rng.normal(0, 1, 3)
            center = p + offset / np.linalg.norm(offset) * species.leaf_size * 0.5
            size = species.leaf_size * scale * rng.uniform(0.8, 1.2)
            cards.append((center, size, w + 0.1, rng.uniform(0, 2 * np.pi)))
    verts = np.zeros((len(cards) * 4, 9), np.float32)
    corners = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)], np.float32)
    for k, (center, size, wind, spin) in enumerate(cards):
        rows = verts[4 * k : 4 * k + 4]
        rows[:, 0:3] = center
        rows[:, 3:5] = corners
        rows[:, 5] = size
        rows[:, 6] = species.leaf_cell
        rows[:, 7] = wind
        rows[:, 8] = spin
    base = np.arange(len(cards), dtype=np.uint32)[:, None] * 4
    indices = (base + np.array([0, 1, 2, 0, 2, 3], np.uint32)).reshape(-1)
    return verts, indices


def _fronds(leaf_branches, species: Species, width: float):
    """A flat ribbon along each branch, tilted down, textured with the frond cell."""
    verts, indices = [], []
    for branch in leaf_branches:
        axis, _ = _transport_frames(branch.points)
        side = np.cross(axis, np.array([0.0, 1.0, 0.0]))
        side /= np.maximum(np.linalg.norm(side, axis=1, keepdims=True), 1e-6)
        side = side - np.array([0.0, 0.25, 0.0])
        normal = np.cross(side, axis)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        normal *= np.sign(normal[:, 1:2] + 1e-6)
        s = np.linspace(0, 1, len(branch.points))
        half = width * (1.0 - 0.6 * s)[:, None]
        base = sum(len(v) for v in verts)
        for sign, u in ((-1, 0.0), (1, 1.0)):
            rows = np.zeros((len(s), 9))
            rows[:, 0:3] = branch.points + sign * side * half
            rows[:, 3:6] = normal
            rows[:, 6] = u
            rows[:, 7] = s
            rows[:, 8] = branch.wind + 0.05
            verts.append(rows)
        n = len(s)
        for i in range(n - 1):
            a, b, c, d = base + i, base + i + 1, base + n + i, base + n + i + 1
            indices += [a, c, b, b, c, d]
    if not verts:
        return np.zeros((0, 9), np.float32), np.zeros(0, np.uint32)
    return np.concatenate(verts).astype(np.float32), np.array(indices, np.uint32)


def generate_tree(species: Species, seed: int = 0) -> TreeModel:
    """A tree of the species with both LODs; the same (species, seed) always gives the same tree."""
    branches = skeleton(species, seed)
    last_level = len(species.children)
    leaf_branches = [b for b in branches if b.level == last_level]
    model = TreeModel(species, seed)
    for radial, per_metre, keep, scale in LOD_DETAIL:
        parts = [_mesh_branch(b, species, radial, per_metre) for b in branches]
        offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
        branch_verts = np.concatenate([v for v, _ in parts]).astype(np.float32)
        branch_idx = np.concatenate([q + o for (_, q), o in zip(parts, offsets)]).astype(np.uint32)
        cards, card_idx = _leaf_cards(leaf_branches, species, np.random.default_rng(seed + 1), keep, scale)
        if species.fronds:
            fronds, frond_idx = _fronds(leaf_branches, species, species.leaf_size * 1.6)
        else:
            fronds, frond_idx = np.zeros((0, 9), np.float32), np.zeros(0, np.uint32)
        model.lods.append(TreeMesh(branch_verts, branch_idx, cards, card_idx, fronds, frond_idx))
    points = np.concatenate([b.points for b in branches])
    model.height = float(points[:, 1].max() + species.leaf_size)
    model.crown_radius = float(np.linalg.norm(points[:, [0, 2]], axis=1).max() + species.leaf_size)
    return model
