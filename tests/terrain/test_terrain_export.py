"""export --terrain: the terrain is its own glTF node with face normals and its relief in the extras."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cityshade.commands import main
from cityshade.maps import load_map
from cityshade.terrain.testing import dem_over

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


def test_the_terrain_exports_as_its_own_mesh(tmp_path):
    import pygltflib

    data = load_map(TAGGED)
    dem = dem_over(tmp_path / "slope.tif", data.crs, data.origin, data.bounds(), lambda x, y: 40.0 + 0.2 * x)
    out = tmp_path / "city.glb"
    assert main(["export", "--map", str(TAGGED), "--terrain", str(dem), "--out", str(out), "--texel", "0.5"]) == 0
    gltf = pygltflib.GLTF2.load(str(out))
    nodes = {node.name: node for node in gltf.nodes}
    assert {"terrain", "ground"} <= set(nodes)
    extras = nodes["terrain"].extras
    assert extras["kind"] == "terrain" and extras["triangles"] > 0
    assert 40.0 - 0.2 * 160 < extras["lowest_m"] < extras["highest_m"] < 40.0 + 0.2 * 160
    import trimesh

    scene = trimesh.load(out, force="scene")
    names = [name for name in scene.graph.nodes_geometry if name.startswith("terrain")]
    normals = np.concatenate([scene.geometry[scene.graph[name][1]].vertex_normals for name in names])
    lying = normals[np.abs(normals[:, 1]) > 0.5]  # the skirts stand upright
    sloped = np.isclose(np.abs(lying[:, 0]) / lying[:, 1], 0.2, atol=0.02)  # beyond the grid the edge runs on flat
    assert len(lying) and sloped.mean() > 0.5, "normals of the 0.2 slope (int8 in the file)"
