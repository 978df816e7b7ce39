"""Trees (`natural=tree` points, and `natural=tree_row` lines planted every TREE_ROW_SPACING metres)
as tree instances: each MapTree at its place and size with the generator's species closest to its
genus or leaf type, and woods filled with trees (deterministic, capped).

Read: `height` and `diameter_crown` (lengths up to 150 and 60 m), `leaf_type`, `genus` (else the
first word of `species` or `taxon`); the guessing model fills the rest (maps/_guess.py)."""

from __future__ import annotations

import zlib
from functools import lru_cache

import numpy as np
import shapely

from ...scene import Layer
from ...trees import SPECIES, SPECIES_ORDER, TREE_DTYPE, generate_tree, tree_instances
from .._model import TREE_ATTRIBUTES, MapData, MapTree, ReadReport, to_scene
from .._tags import length
from ._feature import Built, Feature

NEEDLE_GENERA = ("pinus", "picea", "abies", "larix", "taxus", "juniperus", "thuja", "pseudotsuga", "tsuga", "cedrus")
SLENDER_GENERA = ("populus", "betula", "salix", "alnus", "fraxinus")  # tall crowns: the poplar model
FOREST_SPACING = 7.0  # metres between planted trees in a wood
MAX_FOREST_TREES = 4000  # over all woods of a map: sparser planting beyond this
SCALE_RANGE = (0.3, 2.5)
TREE_ROW_SPACING = 8.0


def species_of(tree: MapTree) -> str:
    """The generator's species for a tree: pine for Pinus, fir for the other conifers (and for a
    needle-leaved tree of no genus), poplar for slender broadleaves, else oak."""
    genus = (tree.genus or "").strip().lower()
    if genus == "pinus":
        return "pine"
    if genus in NEEDLE_GENERA or (not genus and (tree.leaf_type or "") == "needleleaved"):
        return "fir"
    if genus in SLENDER_GENERA:
        return "poplar"
    return "oak"


@lru_cache(maxsize=None)
def model_size(species: str, seed: int) -> tuple[float, float]:
    """(height, crown diameter) in metres of the model the tree pass draws for `species` (same seed)."""
    model = generate_tree(SPECIES[species], seed + SPECIES_ORDER.index(species))
    return model.height, 2.0 * model.crown_radius


def _scale(tree: MapTree, species: str, seed: int) -> float:
    height, crown = model_size(species, seed)
    if tree.height:
        return float(np.clip(tree.height / height, *SCALE_RANGE))
    if tree.crown_diameter:
        return float(np.clip(tree.crown_diameter / crown, *SCALE_RANGE))
    return 1.0


def forest_points(polygon: shapely.Polygon, spacing: float, source_id: str) -> np.ndarray:
    """A jittered grid of points inside `polygon`, the same every time for the same wood."""
    rng = np.random.default_rng(zlib.crc32(source_id.encode()))
    x0, y0, x1, y1 = polygon.bounds
    xs, ys = np.meshgrid(np.arange(x0 + spacing / 2, x1, spacing), np.arange(y0 + spacing / 2, y1, spacing))
    grid = np.c_[xs.ravel(), ys.ravel()] + rng.uniform(-0.35, 0.35, (xs.size, 2)) * spacing
    return grid[shapely.contains_xy(polygon, grid[:, 0], grid[:, 1])] if len(grid) else grid


def forest_trees(map_data: MapData) -> list[MapTree]:
    """Trees planted in the map's woods, FOREST_SPACING apart or sparser to stay under MAX_FOREST_TREES."""
    woods = [a for a in map_data.areas if a.kind == "forest"]
    area = sum(a.polygon.area for a in woods)
    spacing = max(FOREST_SPACING, float(np.sqrt(area / MAX_FOREST_TREES))) if area else FOREST_SPACING
    planted = []
    for wood in woods:
        leaf = wood.tags.get("leaf_type")
        for i, (x, y) in enumerate(forest_points(wood.polygon, spacing, wood.source_id)):
            mixed = (
                leaf if leaf in ("broadleaved", "needleleaved") else ("needleleaved" if i % 3 == 0 else "broadleaved")
            )
            planted.append(MapTree(f"{wood.source_id}#{i}", (float(x), float(y)), leaf_type=mixed))
    return planted[:MAX_FOREST_TREES]


def map_trees(map_data: MapData, seed: int = 0) -> np.ndarray:
    """Tree instance records (trees.TREE_DTYPE) for the map's trees and woods."""
    return tree_records(list(map_data.trees) + forest_trees(map_data), None, seed)


def tree_records(trees: list[MapTree], ground: np.ndarray | None, seed: int = 0) -> np.ndarray:
    """Tree instance records for `trees` standing at heights `ground` (None: 0)."""
    if not trees:
        return np.zeros(0, TREE_DTYPE)
    species = [species_of(t) for t in trees]
    xz = to_scene(np.array([t.position for t in trees], float))
    y = np.zeros(len(xz)) if ground is None else ground
    records = tree_instances(np.c_[xz[:, 0], y, xz[:, 1]], species, np.random.default_rng(seed))
    records["scale"] *= np.array([_scale(t, s, seed) for t, s in zip(trees, species)])
    return records


def tree(source_id: str, position, tags: dict[str, str], report: ReadReport) -> MapTree:
    """A mapped tree with what its tags say (unreadable values counted as fallbacks)."""
    tree = MapTree(source_id, (float(position[0]), float(position[1])))
    for name, key, high in (("height", "height", 150.0), ("crown_diameter", "diameter_crown", 60.0)):
        if key not in tags:
            continue
        value = length(tags[key])
        if value is None or not 0.0 < value <= high:
            report.fallback(key, f"not a length of 0..{high:g} m", f"{source_id} {key}={tags[key][:40]}")
            continue
        setattr(tree, name, value)
        tree.tagged.add(name)
    leaf = tags.get("leaf_type")
    if leaf in ("broadleaved", "needleleaved"):
        tree.leaf_type = leaf
        tree.tagged.add("leaf_type")
    elif leaf is not None:
        report.fallback("leaf_type", "unknown value", f"{source_id} leaf_type={leaf[:40]}")
    species = tags.get("species") or tags.get("taxon")
    genus = tags.get("genus") or (species.split()[0] if species else None)
    if genus:
        tree.genus = genus.strip().capitalize()
        tree.tagged.add("genus")
    tree.species = species
    return tree


def origin_counts(records, attributes) -> dict[str, dict[str, int]]:
    """Per attribute, how many records had it tagged and how many got it guessed."""
    return {
        name: {"tagged": sum(name in r.tagged for r in records), "guessed": sum(name in r.guessed for r in records)}
        for name in attributes
    }


class Trees(Feature):
    name = "trees"

    def point_kind(self, tags):
        return "natural" if tags.get("natural") == "tree" else None

    def wants_line(self, tags):
        return tags.get("natural") == "tree_row"

    def read_point(self, source_id, point, tags, data):
        if tags.get("natural") == "tree":
            data.trees.append(tree(source_id, point, tags, data.report))

    def read_line(self, source_id, lines, tags, data):
        if tags.get("natural") != "tree_row":
            return False
        for line in lines:
            count = max(2, int(round(line.length / TREE_ROW_SPACING)) + 1)
            points = shapely.line_interpolate_point(line, np.linspace(0.0, 1.0, count), normalized=True)
            data.trees += [tree(f"{source_id}#{i}", (p.x, p.y), tags, data.report) for i, p in enumerate(points)]
        return True

    def summary(self, data):
        return {"trees": len(data.trees), "tree_attributes": origin_counts(data.trees, TREE_ATTRIBUTES)}

    def build(self, data):
        return Built(Layer(self.name, trees=map_trees(data)))
