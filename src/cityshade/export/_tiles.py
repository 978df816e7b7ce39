"""3D Tiles 1.1: a tileset.json over glTF tiles. The root holds the ground and trees (refined by
adding); below it a quadtree of building tiles refined by replacement: leaves carry the buildings
at full detail, each coarser level the same buildings as flat-topped prisms with a texel twice as
large. The root transform places the scene's frame (east, north, up after glTF's y-up is turned
z-up) at the map's origin in Earth-centred coordinates (EPSG:4978)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._files import atomic_folder
from ..errors import UsageError
from ..scene import building_vertices
from ._gltf import SCHEMA_ID, building_class, glb_bytes
from ._place import Placement
from ._serve import write_page

LEAF_BUILDINGS = 48  # a tile with more buildings is split into four
MAX_DEPTH = 8


def tileset_schema() -> dict:
    """3D Tiles 1.1 metadata schema: the tileset's own class and the buildings' (their property
    tables are in the tiles' glTF, EXT_structural_metadata, with the same class)."""
    string, real = {"type": "STRING"}, {"type": "SCALAR", "componentType": "FLOAT64"}
    tileset = {
        "attribution": string,
        "crs": dict(string, description="the scene's projected grid (a UTM zone)"),
        "buildings": {"type": "SCALAR", "componentType": "UINT32"},
        "grid_convergence_degrees": dict(real, description="at the origin; content is placed point by point"),
        "grid_scale_factor": dict(real, description="UTM point scale factor at the origin"),
    }
    return {"id": SCHEMA_ID, "classes": {"tileset": {"properties": tileset}, "building": building_class()}}


def box(lo: np.ndarray, hi: np.ndarray) -> list[float]:
    """A 3D Tiles box from glTF content bounds (x east, y up, z south), in the tile frame (x east, y north, z up)."""
    lo_t = np.array([lo[0], -hi[2], lo[1]])
    hi_t = np.array([hi[0], -lo[2], hi[1]])
    centre, half = (lo_t + hi_t) / 2, np.maximum((hi_t - lo_t) / 2, 0.01)
    return [float(v) for v in (*centre, half[0], 0, 0, 0, half[1], 0, 0, 0, half[2])]


class _Node:
    def __init__(self, members: np.ndarray, depth: int, key: str):
        self.members, self.depth, self.key = members, depth, key
        self.children: list[_Node] = []


def quadtree(centres: np.ndarray, members: np.ndarray, depth: int = 0, key: str = "0") -> _Node:
    node = _Node(members, depth, key)
    if len(members) <= LEAF_BUILDINGS or depth >= MAX_DEPTH:
        return node
    mid = np.median(centres[members], axis=0)
    for q, (right, below) in enumerate(((False, False), (True, False), (False, True), (True, True))):
        pick = members[((centres[members, 0] >= mid[0]) == right) & ((centres[members, 1] >= mid[1]) == below)]
        if len(pick):
            node.children.append(quadtree(centres, pick, depth + 1, f"{key}{q}"))
    if len(node.children) == 1:  # all on one point: no split helps
        node.children = []
    return node


def _height(node: _Node) -> int:
    return 0 if not node.children else 1 + max(_height(c) for c in node.children)


def write_tileset(export, out: Path, texel: float, lod: int, encoding, viewer: bool = False) -> dict:
    from ._export import ATTRIBUTION, TILESET_KIND, city_document, summary_of

    if export.origin is None:
        raise UsageError(
            "--format 3dtiles needs a map (--map FILE): a built-in city has no place on Earth; use --format glb"
        )
    place = Placement(export.origin, export.crs)
    masses = list(export.city.masses)  # objects once: read by index below, tile by tile
    bounds = [place.positions(building_vertices(m, i)["position"]) for i, m in enumerate(masses)]
    lo = np.array([b.min(axis=0) for b in bounds])
    hi = np.array([b.max(axis=0) for b in bounds])
    centres = (lo[:, [0, 2]] + hi[:, [0, 2]]) / 2
    tree = quadtree(centres, np.arange(len(masses)))
    totals = {"tiles": 0, "buildings_in_leaves": 0, "levels": _height(tree) + 1}
    stats_all = []

    def tile(node: _Node, folder: Path) -> dict:
        members = node.members
        level = lod + _height(node)  # leaves at lod, each coarser level one more
        gltf, stats = city_document(
            export,
            texel,
            level,
            [masses[i] for i in members],
            [export.metadata[i] for i in members],
            ground=False,
            trees=False,
            place=place,
            encoding=encoding,
        )
        name = f"tiles/b{node.key}.glb"
        (folder / name).write_bytes(glb_bytes(gltf))
        totals["tiles"] += 1
        stats_all.append(stats)
        node_lo, node_hi = lo[members].min(axis=0), hi[members].max(axis=0)
        if node.children:
            diagonal = float(np.linalg.norm((node_hi - node_lo)[[0, 2]]))
            roof = max(masses[i].roof.height for i in members)
            error = max(diagonal / 30.0, roof, 4 * texel * 2**level)
        else:
            error = 0.0
            stats.leaf = True
            totals["buildings_in_leaves"] += stats.buildings
        entry = {
            "boundingVolume": {"box": box(node_lo, node_hi)},
            "geometricError": round(error, 3),
            "refine": "REPLACE",
            "content": {"uri": name},
        }
        if node.children:
            entry["children"] = [tile(c, folder) for c in node.children]
        return entry

    def fill(folder: Path):
        (folder / "tiles").mkdir()
        buildings = tile(tree, folder)
        gltf, stats = city_document(export, texel, lod, [], [], ground=True, trees=True, place=place, encoding=encoding)
        (folder / "tiles/ground.glb").write_bytes(glb_bytes(gltf))
        stats_all.append(stats)
        ground = export.city.ground_mesh
        all_lo, all_hi = lo.min(axis=0), hi.max(axis=0)
        if ground is not None and len(ground):
            placed = place.positions(ground[:, :3])
            all_lo = np.minimum(all_lo, placed.min(axis=0))
            all_hi = np.maximum(all_hi, placed.max(axis=0))
        root_error = max(buildings["geometricError"] * 2, float(np.linalg.norm((all_hi - all_lo)[[0, 2]])) / 10)
        tileset = {
            "schema": tileset_schema(),
            "metadata": {
                "class": "tileset",
                "properties": {
                    "attribution": ATTRIBUTION,
                    "crs": export.crs,
                    "buildings": len(masses),
                    "grid_convergence_degrees": float(np.degrees(place.convergence)),
                    "grid_scale_factor": place.scale,
                },
            },
            "asset": {
                "version": "1.1",
                "generator": "cityshade export",
                "extras": {"attribution": ATTRIBUTION},
            },
            "geometricError": round(root_error * 2, 3),
            "root": {
                "transform": place.transform,
                "boundingVolume": {"box": box(all_lo, all_hi)},
                "geometricError": round(root_error, 3),
                "refine": "ADD",
                "content": {"uri": "tiles/ground.glb"},
                "children": [buildings],
            },
        }
        (folder / "tileset.json").write_text(json.dumps(tileset, indent=1), encoding="utf-8")
        if viewer:
            write_page(folder)

    with atomic_folder(out, TILESET_KIND) as folder:
        fill(folder)
    leaves, ground = stats_all[:-1], stats_all[-1]
    summary = summary_of(ground)
    summary.update(
        totals,
        buildings=totals["buildings_in_leaves"],
        facade_m2=round(sum(s.facade_area for s in leaves if s.leaf), 1),
        triangles=ground.triangles + sum(s.triangles for s in leaves if s.leaf),
        atlas_pages=[list(p) for s in stats_all for p in s.atlas_sizes],
        atlas_texels=sum(s.atlas_texels for s in stats_all),
        draw_calls=sum(s.draw_calls for s in stats_all),
        draw_calls_per_tile={
            "buildings_max": max(s.draw_calls for s in leaves),
            "buildings_mean": round(float(np.mean([s.draw_calls for s in leaves])), 2),
            "ground": ground.draw_calls,
        },
    )
    return summary
