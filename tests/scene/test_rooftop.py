"""What stands on roofs: rooftop units on the flat roofs of blocks and dormers on gabled and hipped
roofs with rooms in them, on the hand-made extract tests/data/maps/roofs_dormers.osm, checked in
numbers (where they stand, how many, closed solids facing out) and in the id pass."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import load_map, map_city
from cityshade.scene import SURFACE_DORMER, SURFACE_ROOF, SURFACE_WALL, building_vertices
from cityshade.scene.testing import (
    CLEARANCE,
    DORMER_SPACING,
    DORMER_WIDTH,
    END_MARGIN,
    HOUSING_ROOF,
    PARAPET_THICKNESS,
    ROOF_PART_SHEET,
    rooftop_units,
    unit_count,
)

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

EXTRACT = Path(__file__).parents[1] / "data" / "maps" / "roofs_dormers.osm"
GABLED, HIPPED, NO_ROOMS, HOUSE, OFFICE, SHOP = range(6)


@pytest.fixture(scope="module")
def masses():
    return map_city(load_map(EXTRACT)).masses


def _tris(v):
    return v["local"].astype(np.float64).reshape(-1, 3, 3)


def _area_vectors(tris):
    return np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]) / 2


def _boxes(v):
    """(low, high) corners of the closed boxes among sheet-metal vertices, 36 rows each."""
    corners = v["local"].astype(np.float64).reshape(-1, 36, 3)
    return corners.min(axis=1), corners.max(axis=1)


def test_units_stand_inside_the_parapet_clear_of_each_other(masses):
    mass = masses[OFFICE]
    v = building_vertices(mass, 0)
    sheet = v[(v["ids"][:, 1] == SURFACE_ROOF) & (v["ids"][:, 2] == ROOF_PART_SHEET)]
    low, high = _boxes(sheet)
    roof = shapely.Polygon(mass.footprint).buffer(-PARAPET_THICKNESS, join_style="mitre")
    assert len(low) == 1 + unit_count(roof.area) and roof.area >= HOUSING_ROOF  # a housing and every unit placed
    assert np.allclose(low[:, 1], mass.wall_top - mass.roof.parapet)  # on the roof, inside the parapet
    footprints = shapely.box(low[:, 0], low[:, 2], high[:, 0], high[:, 2])
    assert shapely.contains(roof.buffer(-CLEARANCE + 1e-6, join_style="mitre"), footprints).all()
    apart = np.array([[a.distance(b) for b in footprints] for a in footprints])
    assert apart[~np.eye(len(footprints), dtype=bool)].min() >= CLEARANCE - 1e-9
    tallest = high[:, 1] - low[:, 1]
    assert tallest.max() >= 2.6 and tallest.min() >= 0.6  # a walk-in housing, knee-high units at least
    tris = _tris(sheet)
    assert np.allclose(_area_vectors(tris).reshape(-1, 12, 3).sum(axis=1), 0.0)  # each box closed
    agree = np.einsum("ij,ij->i", _area_vectors(tris), sheet["normal"][::3].astype(np.float64))
    assert np.all(agree > 0)  # wound to face out


def test_units_follow_the_seed_and_only_blocks_have_them(masses):
    roof = shapely.box(0, 0, 30, 20)
    same = [rooftop_units(roof, 10.0, 5).positions for _ in range(2)]
    assert np.array_equal(*same)
    assert not np.array_equal(same[0], rooftop_units(roof, 10.0, 6).positions)
    for index in (SHOP, NO_ROOMS):  # no parapet (a low building, a pitched roof), no dormers
        v = building_vertices(masses[index], 0)
        assert not np.any((v["ids"][:, 1] == SURFACE_ROOF) & (v["ids"][:, 2] == ROOF_PART_SHEET))
    assert len(rooftop_units(shapely.box(0, 0, 1.5, 1.5), 0.0, 1).positions) == 0  # no room for a unit


def _dormer_fronts(mass):
    """The dormers' fronts (surface SURFACE_DORMER): wall triangles above the walls' top, off the outline."""
    v = building_vertices(mass, 0)
    fronts = v[v["ids"][:, 1] == SURFACE_DORMER].reshape(-1, 3)
    walls = v[v["ids"][:, 1] == SURFACE_WALL].reshape(-1, 3)
    outline = shapely.Polygon(mass.footprint).boundary
    off_outline = shapely.distance(outline, shapely.points(walls["local"][:, :, [0, 2]].mean(axis=1))) > 1e-3
    assert not off_outline.any()  # every other wall piece (walls, gables) stands on the outline
    assert np.all(fronts["local"][:, :, 1].min(axis=1) >= mass.wall_top - 1e-4)
    return fronts


@pytest.mark.parametrize(
    "index,length,depth,hipped", [(GABLED, 24.0, 11.0, False), (HIPPED, 26.0, 12.0, True), (HOUSE, 10.0, 8.0, False)]
)
def test_dormers_run_along_both_eaves_counted_from_the_length(masses, index, length, depth, hipped):
    mass = masses[index]
    fronts = _dormer_fronts(mass)
    normals = fronts["normal"][:, 0].astype(np.float64)
    assert np.allclose(normals[:, 1], 0.0) and np.allclose(np.abs(normals[:, 2]), 1.0)  # facing across the ridge
    centres = fronts["local"].astype(np.float64).mean(axis=1)
    assert np.all(np.sign(normals[:, 2]) == np.sign(centres[:, 2] - depth / 2))  # out of their slope, downhill
    assert fronts["local"][:, :, 1].max() < mass.height - 0.5  # under the ridge
    per_side = [  # fronts DORMER_WIDTH wide, DORMER_SPACING apart: gaps wider than a front between them
        1 + int((np.diff(np.sort(centres[np.sign(normals[:, 2]) == side, 0])) > DORMER_WIDTH).sum()) for side in (-1, 1)
    ]
    gabled_count = int((length - 2 * END_MARGIN) // DORMER_SPACING)
    assert per_side[0] == per_side[1] >= 1
    xs = fronts["local"][:, :, 0]
    if hipped:  # fewer, kept in from the hips by more than the dormers reach up the slope
        assert per_side[0] < gabled_count and xs.min() > 2.0 and xs.max() < length - 2.0
    else:
        assert per_side[0] == gabled_count and xs.min() >= END_MARGIN - 1e-4 and xs.max() <= length - END_MARGIN + 1e-4
    assert np.isclose(np.ptp(xs, axis=1).max(), DORMER_WIDTH)


def test_dormered_roofs_stay_closed_and_no_rooms_no_dormers(masses):
    for index in (GABLED, HIPPED, HOUSE):
        mass = masses[index]
        tris = _tris(building_vertices(mass, 0))
        area = shapely.Polygon(mass.footprint).area
        assert np.allclose(_area_vectors(tris).sum(axis=0), [0.0, area, 0.0], atol=1e-3)
    assert len(_dormer_fronts(masses[NO_ROOMS])) == 0
    assert masses[NO_ROOMS].roof.attic_storey == 0.0 and masses[GABLED].roof.attic_storey > 0.0


def _world_centre(mass) -> tuple[float, float]:
    """World (x, z) of the middle of a mass's outline's bounding box."""
    x, z = np.asarray(mass.footprint).max(axis=0) / 2
    c, s = np.cos(mass.yaw), np.sin(mass.yaw)
    return c * x + s * z + mass.position[0], c * z - s * x + mass.position[1]


def test_dormer_windows_show_rooms_and_units_are_roof_in_the_id_pass(gl_context, masses):
    """The dormered block's south side seen with and without its rooms in the roof: the dormers'
    glass adds pixels of rooms (interior faces) in the id pass; the office's units are roof there."""
    from cityshade.interior import FACE_CODES
    from cityshade.render import Renderer, RenderSettings
    from cityshade.scene import Camera, City

    without = list(masses)
    without[GABLED] = replace(masses[GABLED], roof=replace(masses[GABLED].roof, attic_storey=0.0))
    block, roof = _world_centre(masses[GABLED]), _world_centre(masses[OFFICE])
    front = Camera((block[0], 12.0, block[1] + 21.0), (block[0], 10.0, block[1]), fov_y=50.0)  # from the south
    office = Camera((roof[0], 60.0, roof[1] + 1.0), (roof[0], 17.0, roof[1]), fov_y=40.0)  # from above
    interior = [FACE_CODES[f"FACE_{n}"] for n in ("CEILING", "FLOOR", "WALL_X", "WALL_Z", "FURNITURE", "CURTAIN")]
    rooms = []
    for city_masses in (masses, without):
        city = City("roofs", 0, city_masses, [], (-20.0, -60.0, 120.0, 20.0))
        renderer = Renderer((320, 200), RenderSettings(time_of_day=11.0, trees=False, god_rays=False), ctx=gl_context)
        renderer.set_city(city)
        try:
            ids = renderer.render_ids(front)
            rooms.append(int(((ids[..., 2] == GABLED + 1) & np.isin(ids[..., 0], interior)).sum()))
            if city_masses is masses:
                office_ids = renderer.render_ids(office)
                sheet = np.isin(office_ids[..., 2], [OFFICE + 1])
        finally:
            renderer.release()
    print(f"pixels of rooms behind the block's windows: {rooms[0]} with dormers, {rooms[1]} without")
    assert rooms[0] > rooms[1]
    roof = sheet & (office_ids[..., 0] == FACE_CODES["FACE_ROOF"])
    assert roof.sum() > 0.9 * sheet.sum()  # from above: the roof, its rim and its units


def test_a_tagged_roof_material_without_a_colour_keeps_its_own_colour(masses):
    """roof:material=slate and no roof:colour: the roof is slate grey, not a guessed plaster colour."""
    from cityshade.scene import building_record
    from cityshade.scene.testing import ROOF_MATERIALS, ROOF_SLATE, linear

    record = building_record(masses[HIPPED])
    assert record["roof"][3] == ROOF_SLATE
    assert np.allclose(record["roof"][:3], linear(ROOF_MATERIALS["slate"][1]), atol=1e-6)


def _nearest_triangles(tris: np.ndarray, eye: np.ndarray, dirs: np.ndarray):
    """Per ray (eye, unit dirs (N, 3)): the nearest of triangles (T, 3, 3) hit, both sides (the
    building pass draws without culling), and its barycentric (s, t); -1 where none."""
    a, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    best, which = np.full(len(dirs), np.inf), np.full(len(dirs), -1)
    bary = np.zeros((len(dirs), 2))
    for k in range(len(tris)):  # Moller-Trumbore, all rays against one triangle at a time
        p = np.cross(dirs, e2[k])
        det = p @ e1[k]
        with np.errstate(divide="ignore", invalid="ignore"):
            o = eye - a[k]
            s = (p @ o) / det
            q = np.cross(o, e1[k])
            t = (q @ dirs.T) / det
            dist = (q @ e2[k]) / det
        hit = (np.abs(det) > 1e-12) & (s >= 0) & (t >= 0) & (s + t <= 1) & (dist > 0) & (dist < best)
        best[hit], which[hit], bary[hit] = dist[hit], k, np.column_stack([s, t])[hit]
    return which, bary


def test_dormer_fronts_show_their_rooms_in_the_id_pass_as_the_twin(gl_context, masses):
    """The block's dormers on a grammar building (classical: faces under 5 m would be plain walls):
    each front is one window bay with a room of its own behind the glass, no GrammarFitWarning. The
    id pass with room state against the numpy twin (window-bay glass by the bay texture's texel,
    rooms by cityshade.interior's find_room and trace) on the fronts' pixels, found by casting the
    pixel rays at the building's triangles."""
    import warnings

    from cityshade import assets
    from cityshade.grammar import BUILDING_STYLES
    from cityshade.interior import FACE_CODES, InteriorParams, find_room, room_state, trace
    from cityshade.interior.testing import face_frame, object_to_world
    from cityshade.render import GrammarFitWarning, Renderer, RenderSettings
    from cityshade.scene import Camera, City
    from render_checks import id_edges

    style = {name: number for number, name in BUILDING_STYLES.items()}["classical"]
    city_masses = list(masses)
    mass = city_masses[GABLED] = replace(masses[GABLED], style=style)
    x, z = _world_centre(mass)
    eave = z + 5.5  # the south eave of the 11 m deep block (x east, z south)
    y = mass.wall_top + 1.3
    camera = Camera((x - 3.0, y + 1.5, eave + 9.0), (x - 3.0, y, eave), fov_y=50.0)
    size = (200, 125)
    renderer = Renderer(size, RenderSettings(time_of_day=11.0, trees=False, god_rays=False, lights=0.6), ctx=gl_context)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", GrammarFitWarning)  # the block's faces all fit; its dormers are not counted
            renderer.set_city(City("roofs", 0, city_masses, [], (-20.0, -60.0, 120.0, 20.0)))
        gpu = renderer.render_ids(camera, room_state=True)
        sprites = assets.furniture_sprites()
        params = InteriorParams(
            lights=0.6,
            time=renderer.settings.animation_time,
            variants=renderer.textures.room_variants,
            glass_rect=renderer.textures.glass_rect,
            sprite_alpha=sprites[..., 3] / 255.0,
        )
    finally:
        renderer.release()

    v = building_vertices(mass, GABLED)
    dirs = camera.pixel_rays(size).reshape(-1, 3)
    which, bary = _nearest_triangles(v["position"].astype(np.float64).reshape(-1, 3, 3), camera.eye, dirs)
    rows = v.reshape(-1, 3)
    ref = np.zeros((len(dirs), 4), np.uint32)
    ref[which >= 0, 0] = 255  # the building's other surfaces: not compared, their outline an edge
    ref[which >= 0, 2] = GABLED + 1
    front = (which >= 0) & (rows["ids"][np.maximum(which, 0), 0, 1] == SURFACE_DORMER)
    tri = rows[which[front]]
    s, t = bary[front, :1], bary[front, 1:]
    facade = (1 - s - t) * tri["facade"][:, 0] + s * tri["facade"][:, 1] + t * tri["facade"][:, 2]
    face, columns, normal = tri["face"][:, 0].astype(np.float64), tri["ids"][:, 0, 2:], tri["normal"][:, 0]
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    th, tw = alpha.shape
    col = (np.mod(facade[:, 0] / facade[:, 2], 1.0) * tw).astype(np.int64).clip(0, tw - 1)
    row = (np.mod((facade[:, 1] - face[:, 1]) / facade[:, 3], 1.0) * th).astype(np.int64).clip(0, th - 1)
    glass = alpha[row, col] < 0.5
    out = np.zeros((int(front.sum()), 4), np.uint32)
    out[:, 0], out[:, 2] = FACE_CODES["FACE_EXTERIOR"], GABLED + 1
    window = np.column_stack([facade[glass, :2], facade[glass, :2]])
    room = find_room(window, facade[glass], face[glass], columns[glass], mass, params)
    to_face = face_frame(normal[glass].astype(np.float64))
    d = np.einsum("nij,nj->ni", to_face, dirs[front][glass] @ object_to_world(mass.yaw))
    p = np.column_stack([facade[glass, :2], np.zeros(int(glass.sum()))])
    hit_face, room_ids, _, lit, variant = trace(p, d, room, mass, params)
    out[glass, 0], out[glass, 1], out[glass, 3] = hit_face, room_ids, room_state(lit, variant)
    ref[front] = out
    ref = ref.reshape(size[1], size[0], 4)
    front = front.reshape(size[1], size[0])

    differ = front & np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    state = front & ~differ & (gpu[..., 3] != ref[..., 3])
    interior = [FACE_CODES[f"FACE_{n}"] for n in ("CEILING", "FLOOR", "WALL_X", "WALL_Z", "FURNITURE", "CURTAIN")]
    rooms = front & np.isin(ref[..., 0], interior)
    fronts_seen = len(np.unique(columns[:, 0]))
    print(
        f"dormer front pixels {front.sum()} ({fronts_seen} fronts), of them room pixels {rooms.sum()} in "
        f"{len(np.unique(ref[..., 1][rooms]))} rooms; {differ.sum()} differ in face/room/building "
        f"({(differ & ~id_edges(ref)).sum()} away from the twin's edges), {state.sum()} in room state"
    )
    assert fronts_seen >= 2 and rooms.sum() > 100
    assert len(np.unique(ref[..., 1][rooms])) == fronts_seen  # a room of its own behind every front
    assert not (differ & ~id_edges(ref)).any(), "dormer front pixels differ away from any edge"
    assert differ.sum() <= 0.02 * front.sum()
    assert not state.any()


def test_export_draws_dormer_fronts_of_a_grammar_building_as_window_bays(tmp_path, capsys, masses):
    """glTF export: the house's facade is a baked grammar (brick); its dormers' fronts are window
    bays there too, every front triangle in the window-bay material, none in a facade atlas."""
    import pygltflib

    from cityshade.commands import main
    from cityshade.export import has_grammar

    assert has_grammar(masses[HOUSE])
    out = tmp_path / "dormers.glb"
    assert main(["export", "--map", str(EXTRACT), "--out", str(out), "--texel", "0.25"]) == 0
    capsys.readouterr()
    gltf = pygltflib.GLTF2.load(str(out))
    node = next(n for n in gltf.nodes if n.name == "building way/103")
    triangles = {}
    for primitive in gltf.meshes[node.mesh].primitives:
        name = gltf.materials[primitive.material].name
        corners = (
            primitive.indices if primitive.indices is not None else primitive.attributes.POSITION
        )  # shared vertices are indexed
        triangles[name] = triangles.get(name, 0) + gltf.accessors[corners].count // 3
    fronts = len(_dormer_fronts(masses[HOUSE]))
    print(f"the house's triangles by material: {triangles}; dormer front triangles {fronts}")
    assert fronts >= 2 and triangles.get("window bays") == fronts
