"""cityshade export: the GPU facade bake against its numpy twin, atlas packing, the GLB read back
with trimesh, the 3D Tiles tileset, and bad input (one line, exit 2, nothing written)."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest

from cityshade.assets import LABELS
from cityshade.commands import main
from cityshade.export import Canvas, GpuBaker, bake_reference, pack
from cityshade.grammar import facade_seed_vector, library_texture, seed_vector

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


def test_gpu_bake_matches_numpy_twin(gl_context):
    from cityshade.assets import tile_array

    compiled = library_texture()
    tiles = tile_array(128)
    canvases = [
        Canvas(
            0,
            0,
            -0.25,
            -0.25,
            60,
            80,
            14.0,
            19.0,
            compiled.address("classical"),
            seed_vector(3),
            seed_vector(3),
            (4, 3.2),
            1,
        ),
        Canvas(
            1,
            4,
            -0.3,
            2.0,
            50,
            40,
            12.0,
            9.0,
            compiled.address("office"),
            facade_seed_vector(4, 4),
            seed_vector(4),
            (4, 3.2),
            1,
        ),
        Canvas(
            2, 0, -0.25, -0.25, 60, 80, 14.0, 19.0, compiled.address("brick"), *[seed_vector(5)] * 2, (4, 3.2), 1, 2
        ),
        Canvas(
            3,
            6,
            -0.25,
            5.75,
            40,
            60,
            9.5,
            14.0,
            compiled.address("storeys"),
            facade_seed_vector(5, 6),
            seed_vector(5),
            (4, 3.2),
            1,
            2,
            base=6.0,
            values=(4.0, 0.0, 0.0, 20.0),
        ),
    ]  # a face: its own seed, the building's for its spandrels; a raised part's face (facade.level 2), and
    # one starting 6 m up with 4 storeys (building.levels)
    size = pack(canvases)[0]
    baker = GpuBaker(gl_context, tiles, nearest=True)
    page = baker.bake_page(canvases, size, 0.25)
    baker.release()
    for canvas in canvases:
        reference = bake_reference(canvas, 0.25, tiles)
        region = (slice(canvas.y, canvas.y + canvas.rows), slice(canvas.x, canvas.x + canvas.cols))
        ids = np.any(page["ids"][region] != reference["ids"], axis=-1)
        assert ids.sum() == 0, f"{ids.sum()} of {ids.size} texels differ in ids"
        for name in ("colour", "normal"):
            differ = np.abs(page[name][region] - reference[name]).max(axis=-1) > 2e-3
            assert differ.sum() == 0, f"{differ.sum()} of {differ.size} {name} texels differ"
        assert len(np.unique(reference["ids"][..., 1])) >= 2  # at least walls and windows: a real facade
        doors = int(np.count_nonzero(reference["ids"][..., 1] == LABELS.index("door")))
        assert (doors == 0) == (canvas.level > 0), (canvas.start, doors)  # a ground floor only at level 0


def test_every_wall_face_gets_a_canvas_in_its_true_size():
    """As the renderer scopes its grammar: one canvas per face (a curved run of walls is one face, each
    ring of a dome another), as wide as the face's walls are long, from its base to its top."""
    from cityshade.export import canvases_of, has_grammar, wall_sides
    from cityshade.scene import SURFACE_WALL, building_vertices, cylinder, dome, make_city

    extra = [cylinder((0.0, 0.0), 16.0, 20.0, style=3), dome((0.0, 0.0), 30.0, style=4)]
    masses = [m for m in make_city("outlines").masses if has_grammar(m)] + extra
    assert {m.shape for m in masses} == {"prism", "cylinder", "dome"}
    texel = 0.25
    for index, mass in enumerate(masses):
        vertices = building_vertices(mass, index)
        walls = vertices[vertices["ids"][:, 1] == SURFACE_WALL]
        canvases = canvases_of(index, mass, walls, texel)
        sides = wall_sides(walls)
        assert len(canvases) == sides.max() + 1 >= (3 if mass.shape == "dome" else 1)
        for side, canvas in enumerate(canvases):
            face = walls[sides == side]
            bottom = face[np.isclose(face["facade"][:, 1], face["facade"][:, 1].min())]
            run = np.unique(np.column_stack([bottom["facade"][:, 0], bottom["local"][:, [0, 2]]]), axis=0)
            length = np.linalg.norm(np.diff(run[:, 1:], axis=0), axis=1).sum()  # along the walls, point to point
            if mass.shape == "dome":  # a ring's width is its circle half way up; its bottom circle is wider
                assert length > canvas.width * 0.99
            else:
                assert canvas.width == pytest.approx(length, rel=1e-3)
            low, high = face["facade"][:, 1].min(), face["facade"][:, 1].max()
            assert canvas.base == pytest.approx(low, abs=1e-4) and canvas.height == pytest.approx(high - low, abs=1e-4)
            assert canvas.u0 == pytest.approx(-texel, abs=1e-4)
            assert canvas.cols == int(np.ceil(canvas.width / texel - 1e-6)) + 2
        if mass.shape == "dome":  # ring k starts k storeys up: facade.level k
            assert [c.level for c in sorted(canvases, key=lambda c: c.base)] == list(range(len(canvases)))


def test_pack_places_canvases_without_overlap():
    rng = np.random.default_rng(1)
    canvases = [
        Canvas(i, 0, 0, 0, int(w), int(h), 1, 1, 0, (0, 0), (0, 0), (1, 1), 1)
        for i, (w, h) in enumerate(rng.integers(1, 700, (60, 2)))
    ] + [Canvas(99, 0, 0, 0, 3000, 40, 1, 1, 0, (0, 0), (0, 0), (1, 1), 1)]
    sizes = pack(canvases)
    for page, (cols, rows) in enumerate(sizes):
        used = np.zeros((rows, cols), np.int32)
        for c in canvases:
            if c.page == page:
                used[c.y : c.y + c.rows, c.x : c.x + c.cols] += 1
        assert used.max() == 1 and used.shape[0] >= max(c.y + c.rows for c in canvases if c.page == page)
    assert all(c.page >= 0 for c in canvases)
    assert max(max(size) for size in sizes[:-1]) <= 2048 and sizes[-1] == (3000, 40)  # a wide canvas: its own page


def _summary(capsys) -> dict:
    return json.loads(capsys.readouterr().out.strip().splitlines()[-1])


def test_glb_round_trip_with_trimesh(tmp_path, capsys):
    import pygltflib
    import trimesh

    from cityshade.maps import load_map, map_city
    from cityshade.scene import building_vertices

    out = tmp_path / "tagged.glb"
    assert main(["export", "--map", str(TAGGED), "--out", str(out), "--texel", "0.25"]) == 0
    summary = _summary(capsys)
    city = map_city(load_map(TAGGED))
    scene = trimesh.load(out, force="scene")
    buildings = [name for name in scene.graph.nodes_geometry if name.startswith("building ")]
    # trimesh loads each primitive (walls per atlas side, roof) as a node named after its mesh + "_suffix"
    assert len({name.split("_")[0] for name in buildings}) == summary["buildings"] == len(city.masses)
    building_triangles = sum(len(scene.geometry[scene.graph[name][1]].faces) for name in buildings)
    assert building_triangles == sum(len(building_vertices(m, i)) // 3 for i, m in enumerate(city.masses))
    total = sum(len(scene.geometry[scene.graph[name][1]].faces) for name in scene.graph.nodes_geometry)
    assert total == summary["triangles"]  # trees once per species: the instancing extension is read by few
    gltf = pygltflib.GLTF2.load(str(out))
    facade_images = [im for im in gltf.images if (im.name or "").startswith("facade colour")]
    assert len(facade_images) == len(summary["atlas_pages"]) >= 1
    textures = [
        m
        for m in scene.geometry.values()
        if getattr(m.visual, "material", None) is not None
        and getattr(m.visual.material, "baseColorTexture", None) is not None
    ]
    sizes = {tuple(m.visual.material.baseColorTexture.size) for m in textures}
    assert {tuple(p) for p in summary["atlas_pages"]} <= sizes
    extras = {n.extras["source_id"]: n.extras for n in gltf.nodes if n.name.startswith("building ")}
    # the outline is drawn as its parts, and under the one that floats (way/101, from 3 m) up to its base
    assert extras["way/100"]["kind"] == "office"
    part = extras["way/101"]
    assert part["part"] and part["part_of"] == "way/100" and part["tags"]["min_height"] == "3"
    assert part["height"] == 30 and "height" in part["tagged"] and "height" not in part["guessed"]
    courtyard = extras["relation/200"]
    assert courtyard["tags"]["building"] == "apartments" and "height" in courtyard["guessed"]
    assert gltf.asset.extras["origin"]["longitude"] == pytest.approx(24.94, abs=0.01)
    assert gltf.asset.extras["crs"].startswith("EPSG:")
    assert "EXT_mesh_gpu_instancing" in gltf.extensionsUsed
    assert _property_strings(gltf, "source_id") == [
        n.extras["source_id"] for n in gltf.nodes if n.name.startswith("building ")
    ]
    for node in (n for n in gltf.nodes if n.name.startswith("building ")):
        # its origin at the middle of its base: the quantized positions around it reach its size only
        materials = [p.material for p in gltf.meshes[node.mesh].primitives]
        assert len(set(materials)) == len(materials)  # one primitive per material
        accessors = [gltf.accessors[p.attributes.POSITION] for p in gltf.meshes[node.mesh].primitives]
        low = np.min([a.min for a in accessors], axis=0) * node.scale
        high = np.max([a.max for a in accessors], axis=0) * node.scale
        assert low[1] == pytest.approx(0.0, abs=0.01) and np.allclose(-low[[0, 2]], high[[0, 2]], atol=0.01)
        assert np.all(high - low <= [120.0, node.extras["height"] + 1.0, 120.0])


def _property_strings(gltf, name: str) -> list[str]:
    """A STRING property of the EXT_structural_metadata table, decoded from the binary buffer."""
    table = gltf.extensions["EXT_structural_metadata"]["propertyTables"][0]
    blob = gltf.binary_blob()

    def view(index):
        v = gltf.bufferViews[index]
        return blob[v.byteOffset : v.byteOffset + v.byteLength]

    prop = table["properties"][name]
    offsets = np.frombuffer(view(prop["stringOffsets"]), np.uint32)
    data = view(prop["values"])
    return [data[a:b].decode("utf-8") for a, b in itertools.pairwise(offsets)]


def test_tileset_hierarchy_and_earth_position(tmp_path, capsys):
    out = tmp_path / "tiles"
    assert main(["export", "--map", str(TAGGED), "--out", str(out), "--format", "3dtiles", "--texel", "0.5"]) == 0
    summary = _summary(capsys)
    tileset = json.loads((out / "tileset.json").read_text())
    assert tileset["asset"]["version"] == "1.1"
    root = tileset["root"]
    translation = np.asarray(root["transform"][12:15])
    assert 6.35e6 < np.linalg.norm(translation) < 6.40e6  # on the Earth's surface (metres from its centre)
    axes = np.asarray(root["transform"]).reshape(4, 4)[:3, :3]
    assert np.allclose(axes @ axes.T, np.eye(3), atol=1e-9)

    def walk(tile, parent_error):
        assert tile["geometricError"] <= parent_error
        assert (out / tile["content"]["uri"]).is_file()
        children = tile.get("children", [])
        if not children:
            assert tile["geometricError"] == 0
        return 1 + sum(walk(child, tile["geometricError"]) for child in children)

    assert walk(root, tileset["geometricError"]) == summary["tiles"] + 1
    import pygltflib

    counts = []
    for tile in (out / "tiles").glob("b*.glb"):  # a building tile: one node, one primitive per material
        gltf = pygltflib.GLTF2.load(str(tile))
        materials = [p.material for p in gltf.meshes[0].primitives]
        assert len(gltf.meshes) == 1 and len(set(materials)) == len(materials)
        counts.append(len(materials))
    assert summary["draw_calls_per_tile"]["buildings_max"] == max(counts)
    assert summary["buildings"] == 5  # two parts, the outline under the floating one, a courtyard block, a canopy


def _check_sizes(texel: float):
    from cityshade.export import canvases_of, has_grammar, map_export_city
    from cityshade.export.testing import check_size
    from cityshade.scene import building_vertices

    city = map_export_city(TAGGED).city
    canvases = []
    for i, mass in enumerate(city.masses):
        verts = building_vertices(mass, i)
        if has_grammar(mass):
            canvases += canvases_of(i, mass, verts[verts["ids"][:, 1] == 0], texel)
    assert canvases
    check_size(canvases, texel)


def _fails(args, capsys) -> str:
    code = main(args)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err
    return err


def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys):
    base = ["export", "--map", str(TAGGED)]
    out = tmp_path / "city.glb"
    err = _fails(base + ["--out", str(out), "--region", "10,10,10.1,10.1"], capsys)
    assert "--region" in err and "no building" in err
    err = _fails(base + ["--out", str(out), "--texel", "0.0001"], capsys)
    assert "--texel" in err and "use --texel" in err
    suggested = float(err.split("use --texel ")[1].split()[0])
    _check_sizes(suggested)  # the advice holds (without baking the atlas)
    err = _fails(base + ["--out", str(out), "--format", "obj"], capsys)
    assert "obj" in err and "glb" in err
    err = _fails(base + ["--out", str(tmp_path / "t"), "--format", "3dtiles", "--region", "0,0,1,1"], capsys)
    assert "--region" in err
    a_file = tmp_path / "notes.txt"
    a_file.write_text("x")
    err = _fails(base + ["--out", str(a_file / "city.glb")], capsys)
    assert "cannot write" in err
    err = _fails(base + ["--out", "/proc/cityshade-export.glb", "--texel", "1"], capsys)  # even root cannot
    assert "cannot write" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]  # no partial file, tileset or temporary
    err = _fails(base + ["--out", str(tmp_path), "--format", "3dtiles"], capsys)  # would replace notes.txt
    assert "is not an earlier output of this command" in err and a_file.read_text() == "x"


def test_region_keeps_what_lies_inside_as_gltf(tmp_path, capsys):
    import pygltflib

    out = tmp_path / "corner.gltf"
    # around way/400 only (a fuel station canopy at 60.1711-60.1712 N, 24.9400-24.9401 E)
    assert (
        main(
            [
                "export",
                "--map",
                str(TAGGED),
                "--out",
                str(out),
                "--region",
                "24.9399,60.1710,24.9402,60.1713",
                "--texel",
                "0.5",
            ]
        )
        == 0
    )
    assert _summary(capsys)["buildings"] == 1
    gltf = pygltflib.GLTF2.load(str(out))
    assert [n.name for n in gltf.nodes] == ["building way/400", "ground"]
    node = gltf.nodes[1]
    ground = gltf.accessors[gltf.meshes[node.mesh].primitives[0].attributes.POSITION]
    width = (ground.max[0] - ground.min[0]) * (node.scale or [1.0])[0]  # quantized: in units of the node's scale
    assert ground.count > 0 and width <= 17.7 + 1e-3  # cut to the region's 17.7 m width


def test_faces_too_narrow_for_the_grammar_are_plain_walls_as_in_the_renderer(gl_context):
    """A 4 m wide brick block (brick fits 5 m faces): its two narrow ends get no canvas but a plain
    wall in the grammar's wall colour, as the renderer draws them, with the renderer's counted warning."""
    from cityshade.export.testing import BuildingWriter, Document, Stats
    from cityshade.render import GrammarFitWarning
    from cityshade.scene import box

    doc = Document({})
    with pytest.warns(GrammarFitWarning, match="2 wall faces"):
        writer = BuildingWriter(
            doc, [box((0.0, 0.0), 4.0, 20.0, 12.0, style=4)], [{"source_id": "way/1"}], 0.5, Stats()
        )
    assert len(writer.canvases[0]) == 2  # the long sides
    assert {c.width for c in writer.canvases[0]} == {20.0}
    writer.write()
    names = [doc.gltf.materials[p.material].name for mesh in doc.gltf.meshes for p in mesh.primitives]
    # one primitive per material: both canvases lie on the one atlas page
    assert sorted(names) == ["facades 0", "plain walls", "roofs"]


def test_a_baked_dome_has_unit_normals_and_tangents(gl_context):
    """A dome's rings lean inwards: their tangents along the ring (glTF requires unit vectors) are
    normalised, not the horizontal part of the normal turned."""
    from cityshade.export import Encoding
    from cityshade.export.testing import BuildingWriter, Document, Stats
    from cityshade.scene import dome

    doc = Document({}, encoding=Encoding(geometry="plain"))  # accessors read as they are
    writer = BuildingWriter(doc, [dome((0.0, 0.0), 30.0, style=4)], [{"source_id": "way/1"}], 0.5, Stats())
    assert len(writer.canvases[0]) >= 3  # baked ring by ring
    writer.write()
    gltf = doc.finish()
    blob = gltf.binary_blob()

    def read(index, width):
        accessor = gltf.accessors[index]
        view = gltf.bufferViews[accessor.bufferView]
        return np.frombuffer(blob, np.float32, accessor.count * width, view.byteOffset).reshape(-1, width)

    tangents = [read(p.attributes.TANGENT, 4) for m in gltf.meshes for p in m.primitives if p.attributes.TANGENT]
    normals = [read(p.attributes.NORMAL, 3) for m in gltf.meshes for p in m.primitives]
    assert tangents and np.allclose(np.linalg.norm(np.concatenate(tangents)[:, :3], axis=1), 1.0, atol=1e-5)
    assert np.allclose(np.linalg.norm(np.concatenate(normals), axis=1), 1.0, atol=1e-5)


@pytest.mark.parametrize(
    "option, value, allowed",
    [
        ("--texel", "inf", "more than 0 and at most 100"),
        ("--texel", "1e308", "more than 0 and at most 100"),
        ("--texel", "nan", "more than 0 and at most 100"),
        ("--texel", "-1", "more than 0 and at most 100"),
        ("--lod", "2000", "from 0 (full detail) to 16"),
        ("--lod", "-1", "from 0 (full detail) to 16"),
    ],
)
@pytest.mark.parametrize("fmt", ["glb", "3dtiles"])
def test_texel_and_lod_out_of_range_are_one_line(option, value, allowed, fmt, tmp_path, capsys):
    out = tmp_path / "out"
    err = _fails(["export", "--map", str(TAGGED), "--format", fmt, "--out", str(out), option, value], capsys)
    assert f"{option} {float(value) if option == '--texel' else value}" in err and allowed in err
    assert not list(tmp_path.iterdir())


FAR_EAST = Path(__file__).parents[1] / "data" / "export" / "far_from_meridian.osm"


def _osm_building_nodes(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(lon, lat) of every node of the file's building ways, and each one's building height tag."""
    import xml.etree.ElementTree as ET

    root = ET.parse(path).getroot()
    nodes = {n.get("id"): (float(n.get("lon")), float(n.get("lat"))) for n in root.iter("node")}
    points, heights = [], []
    for way in root.iter("way"):
        tags = {t.get("k"): t.get("v") for t in way.iter("tag")}
        if "building" in tags:
            refs = {nd.get("ref") for nd in way.iter("nd")}
            points += [nodes[r] for r in sorted(refs)]
            heights += [float(tags["height"])] * len(refs)
    return np.asarray(points), np.asarray(heights)


def test_tileset_vertices_lie_on_their_osm_nodes_far_from_the_central_meridian(tmp_path, capsys):
    """Blocks spread over 4 x 2 km, 2.6 degrees east of their UTM zone's central meridian (grid
    convergence 2.4 degrees, scale factor 0.99972): every corner of every block, at the ground and at
    its roof, has an exported vertex within 0.5 m of pyproj's ECEF of its OSM node. Turning the scene
    by one rotation at the origin put them up to 80 m off."""
    import pyproj

    from cityshade.export.testing import tileset_points

    out = tmp_path / "tiles"
    assert main(["export", "--map", str(FAR_EAST), "--out", str(out), "--format", "3dtiles", "--texel", "1"]) == 0
    summary = _summary(capsys)
    assert summary["buildings"] == 5
    tileset = json.loads((out / "tileset.json").read_text())
    properties = tileset["metadata"]["properties"]  # the tileset's metadata, in its schema's class
    assert set(properties) == set(tileset["schema"]["classes"][tileset["metadata"]["class"]]["properties"])
    assert properties["grid_convergence_degrees"] == pytest.approx(2.44, abs=0.05)
    assert properties["grid_scale_factor"] == pytest.approx(0.99972, abs=2e-5)
    exported = tileset_points(out)
    lonlat, heights = _osm_building_nodes(FAR_EAST)
    to_ecef = pyproj.Transformer.from_crs("EPSG:4979", "EPSG:4978", always_xy=True)
    from scipy.spatial import cKDTree

    tree = cKDTree(exported)
    for h in (np.zeros(len(heights)), heights):
        expected = np.column_stack(to_ecef.transform(lonlat[:, 0], lonlat[:, 1], h))
        distance, _ = tree.query(expected)
        assert len(distance) == 20 and distance.max() <= 0.5, f"{np.sort(distance)[-5:]} m"


@pytest.mark.parametrize(
    "extents",
    [
        [[1000.0, 30.0]],  # one face too wide for an 8192-texel side at 0.05 m
        [[100.0, 30.0]] * 2000,  # 2.4 billion texels at 0.05 m: over the total
    ],
)
def test_the_default_texel_is_the_finest_that_fits(extents):
    from cityshade.export import ATLAS_LIMIT
    from cityshade.export.testing import finest_texel

    extents = np.asarray(extents)
    texel = finest_texel(extents, 0.05)

    def fits(t):
        sides = np.ceil((extents + 2 * t) / t)
        return sides.max() <= ATLAS_LIMIT and np.prod(sides, axis=1).sum() <= 1 << 28

    assert texel > 0.05 and fits(texel)
    step = 10 ** (np.floor(np.log10(texel)) - 2)  # its third significant digit
    assert not fits(texel - step)
    assert finest_texel(extents[:1] / 100, 0.05) == 0.05  # small facades: the finest allowed


@pytest.mark.slow  # a bake at 0.05 m: a few seconds
def test_export_without_texel_chooses_and_prints_it(tmp_path, capsys):
    out = tmp_path / "far.glb"
    one_block = ["--region", "29.599,69.709,29.602,69.712"]  # 23 x 11 x 22 m: small enough to bake at 0.05 m
    assert main(["export", "--map", str(FAR_EAST), "--out", str(out), *one_block]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out.strip().splitlines()[-1])
    assert summary["texel"] == 0.05 and summary["buildings"] == 1
    assert "--texel 0.05: the finest texel" in captured.err


def test_lit_windows_follow_each_use_through_the_day():
    """The share of lit rooms follows the renderer's schedule per use (scene.lit_share): an office
    block is lit at noon and nearly dark at 23:00, a home the other way round."""
    from cityshade.export.testing import lit_rooms
    from cityshade.scene import USES, lit_share

    def canvas(use):  # 100 x 60 rooms of 1 x 1 m, one texel each
        return Canvas(
            0, 0, 0.0, 0.0, 100, 60, 100.0, 60.0, 0, (0.0, 0.0), (0.0, 0.0), (1.0, 1.0), 1.0, values=(20, 0, use, 60)
        )

    for name in ("office", "home"):
        for hours in (12.0, 23.0):
            lit = lit_rooms(canvas(USES[name]), 1.0, hours).mean()
            assert lit == pytest.approx(lit_share(USES[name], hours), abs=0.03), (name, hours)
    assert (
        lit_rooms(canvas(USES["office"]), 1.0, 12.0).mean()
        > 0.7
        > 0.1
        > lit_rooms(canvas(USES["office"]), 1.0, 23.0).mean()
    )


def test_facades_glow_only_in_the_night_variant(tmp_path, capsys):
    """The facade materials are the day's (no emissive map) with a night variant
    (KHR_materials_variants) whose emissive map lights windows."""
    import io

    import pygltflib
    from PIL import Image

    out = tmp_path / "tagged.glb"
    assert main(["export", "--map", str(TAGGED), "--out", str(out), "--texel", "0.5"]) == 0
    gltf = pygltflib.GLTF2.load(str(out))
    assert [v["name"] for v in gltf.extensions["KHR_materials_variants"]["variants"]] == ["day", "night"]
    facades = [p for m in gltf.meshes for p in m.primitives if gltf.materials[p.material].name.startswith("facades")]
    assert facades
    blob = gltf.binary_blob()
    for primitive in facades:
        day = gltf.materials[primitive.material]
        mappings = {m["variants"][0]: m["material"] for m in primitive.extensions["KHR_materials_variants"]["mappings"]}
        night = gltf.materials[mappings[1]]
        assert mappings[0] == primitive.material and day.emissiveTexture is None
        texture = gltf.textures[night.emissiveTexture.index]
        view = gltf.bufferViews[gltf.images[texture.extensions["EXT_texture_webp"]["source"]].bufferView]
        glow = np.asarray(Image.open(io.BytesIO(blob[view.byteOffset : view.byteOffset + view.byteLength])))
        assert (glow.max(axis=-1) > 0).any()


def test_trees_as_nodes_are_read_by_trimesh_one_per_tree(tmp_path, capsys):
    """--trees nodes: every tree a node showing its species' one mesh (core glTF), so readers
    without EXT_mesh_gpu_instancing (trimesh) still place every tree."""
    import trimesh

    out = tmp_path / "trees.glb"
    assert main(["export", "--map", str(TAGGED), "--out", str(out), "--texel", "1", "--trees", "nodes"]) == 0
    summary = _summary(capsys)
    scene = trimesh.load(out, force="scene")
    places = {
        tuple(np.round(scene.graph[name][0][:3, 3], 3))
        for name in scene.graph.nodes_geometry
        if scene.graph[name][1].startswith("trees")
    }
    assert summary["tree_instances"] >= 2 and len(places) == summary["tree_instances"]


def test_draco_geometry_and_png_textures_read_back_with_trimesh(tmp_path, capsys):
    """--geometry draco --textures png: the Draco buffers decode (DracoPy, through trimesh) to the
    scene's triangles, and the images are core PNG (no WebP extension required)."""
    import pygltflib
    import trimesh

    out = tmp_path / "draco.glb"
    args = ["--texel", "1", "--geometry", "draco", "--textures", "png"]
    assert main(["export", "--map", str(TAGGED), "--out", str(out), *args]) == 0
    summary = _summary(capsys)
    gltf = pygltflib.GLTF2.load(str(out))
    assert gltf.extensionsRequired == ["KHR_draco_mesh_compression"]
    assert {im.mimeType for im in gltf.images} == {"image/png"}
    scene = trimesh.load(out, force="scene")
    assert sum(len(scene.geometry[scene.graph[n][1]].faces) for n in scene.graph.nodes_geometry) == summary["triangles"]


@pytest.mark.parametrize("geometry", ["quantized", "plain"])
def test_indices_widen_past_65535_vertices(geometry):
    import pygltflib

    from cityshade.export import Encoding
    from cityshade.export.testing import Document

    doc = Document({}, encoding=Encoding(geometry=geometry))
    for count, component in ((65535, pygltflib.UNSIGNED_SHORT), (65536, pygltflib.UNSIGNED_INT)):
        positions = np.random.default_rng(1).uniform(-10, 10, (count, 3))
        normals = np.tile([0.0, 1.0, 0.0], (count, 1))
        primitive = doc.primitive(0, positions, normals, indices=np.arange(count // 3 * 3), scale=10 / 32767)
        assert doc.gltf.accessors[primitive.indices].componentType == component


@pytest.mark.parametrize(
    "option, value, allowed",
    [
        ("--textures", "ktx2", "webp, png"),
        ("--geometry", "meshopt", "quantized, draco, plain"),
        ("--trees", "x", "instanced, nodes"),
    ],
)
def test_unknown_encodings_are_one_line_before_the_map_is_read(option, value, allowed, tmp_path, capsys):
    out = tmp_path / "city.glb"
    err = _fails(["export", "--map", str(tmp_path / "absent.osm"), "--out", str(out), option, value], capsys)
    assert option in err and allowed in err and not out.exists()
