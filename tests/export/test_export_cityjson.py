"""Export of a CityJSON city: its faces as given, heights as given, each object's id."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cityshade.commands import main

DEN_HAAG = Path(__file__).parents[1] / "data" / "cityjson" / "den_haag_lod2.city.json"


@pytest.mark.slow  # about 10 s: the facade bake on llvmpipe
def test_glb_of_a_cityjson_city_keeps_its_faces_and_heights(tmp_path, capsys):
    import pygltflib
    import trimesh

    from cityshade.maps import load_map, map_city
    from cityshade.scene import building_vertices

    out = tmp_path / "den_haag.glb"
    assert main(["export", "--map", str(DEN_HAAG), "--out", str(out), "--texel", "0.5"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    data = load_map(DEN_HAAG)
    city = map_city(data)
    assert summary["buildings"] == len(city.masses) == 12
    scene = trimesh.load(out, force="scene")
    buildings = [name for name in scene.graph.nodes_geometry if name.startswith("building ")]
    triangles = sum(len(scene.geometry[scene.graph[name][1]].faces) for name in buildings)
    assert triangles == sum(len(building_vertices(m, i)) // 3 for i, m in enumerate(city.masses))
    extras = [n.extras for n in pygltflib.GLTF2.load(str(out)).nodes if n.name.startswith("building ")]
    parts = {b.source_id for b in data.buildings if b.is_part}
    assert len(extras) == 12 and all(e["source_id"] in {b.source_id for b in data.buildings} for e in extras)
    assert sum(e["part"] for e in extras) == sum(e["source_id"] in parts for e in extras) >= 7  # the BuildingParts
    top = float(scene.dump(concatenate=True).bounds[1][1])
    assert top == pytest.approx(max(m.height for m in city.masses), abs=0.01)  # heights as given (NAP)
