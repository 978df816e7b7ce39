"""Roofs of map buildings: every roof shape and Simple 3D Buildings tag on small hand-made buildings,
checked in numbers (heights, ridge direction, volumes, closed surfaces, outward normals)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import ROOF_SHAPES, MapBuilding, MapData, building_masses, facade_style
from cityshade.scene import SURFACE_ROOF, building_record, building_vertices, rotation_y
from cityshade.scene.testing import ROOF_PART_SHEET, ROOF_PART_SURFACE

WALL_TOP = 10.0
RISE = 4.0


def masses_of(*buildings):
    return building_masses(MapData(Path("roofs.osm"), (24.94, 60.17), "EPSG:32635", list(buildings)))


def one(outline=None, **tags):
    tags.setdefault("height", WALL_TOP + (RISE if tags.get("roof_shape", "flat") != "flat" else 0.0))
    if tags.get("roof_shape", "flat") != "flat":
        tags.setdefault("roof_height", RISE)
    building = MapBuilding(0, "way/1", outline if outline is not None else shapely.box(0, 0, 20, 10), **tags)
    (mass,) = masses_of(building)
    return mass


def triangles(mass, surface=None, part=None):
    """(triangles, world normals) of a mass, of one surface kind and roof part if given."""
    v = building_vertices(mass, 0)
    if surface is not None:
        v = v[v["ids"][:, 1] == surface]
    if part is not None:
        v = v[v["ids"][:, 2] == part]
    normals = v["normal"].reshape(-1, 3, 3)[:, 0].astype(np.float64) @ rotation_y(mass.yaw).T  # object -> world
    return v["position"].astype(np.float64).reshape(-1, 3, 3), normals


def area_vectors(tris):
    return np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]) / 2


def volume(tris):
    """Volume enclosed with the ground (the mesh has no floor): divergence theorem with the floor at y=0."""
    return float(np.einsum("ij,ij->i", tris[:, 0], area_vectors(tris) * 2).sum() / 6)


def closure(tris):
    """The sum of the outward area vectors: (0, floor area, 0) for a closed mass standing on the ground."""
    return area_vectors(tris).sum(axis=0)


def assert_closed_and_outward(mass, outline, smooth=False):
    """Closed but for the floor, no degenerate triangles, normals that agree with the winding (on the
    same side of it where the surface is shaded smooth), and every wall facing out of the outline
    (map metres: scene (x, z) is map (x, -y))."""
    tris, normals = triangles(mass)
    area = area_vectors(tris)
    assert np.allclose(closure(tris), [0.0, outline.area, 0.0], atol=1e-3), closure(tris)
    length = np.linalg.norm(area, axis=1)
    assert length.min() > 1e-9, "no degenerate triangles"
    agree = np.einsum("ij,ij->i", area / length[:, None], normals)
    assert np.all(agree > (0.5 if smooth else 0.999))
    walls = np.abs(normals[:, 1]) < 1e-6
    centres = tris[walls].mean(axis=1)[:, [0, 2]]
    step = 0.01 * normals[walls][:, [0, 2]]
    to_map = np.array([1.0, -1.0])
    assert not shapely.contains_xy(outline, *((centres + step) * to_map).T).any(), "walls face out"
    assert shapely.contains_xy(outline, *((centres - step) * to_map).T).all()


def roof_points(mass):
    tris, _ = triangles(mass, SURFACE_ROOF)
    return tris.reshape(-1, 3)


EXPECTED_VOLUME = {  # a 20 x 10 m outline, walls 10 m, roof 4 m
    "flat": 2000.0,
    "gabled": 2000.0 + 0.5 * 10 * RISE * 20,
    "skillion": 2000.0 + 0.5 * 10 * RISE * 20,
    "saltbox": 2000.0 + 0.5 * 10 * RISE * 20,
    "pyramidal": 2000.0 + 200 * RISE / 3,
    "hipped": 2000.0 + 0.5 * 10 * RISE * 20 - 2 * (0.5 * 10 * RISE * 5 - 10 * 5 * RISE / 3),
}


@pytest.mark.parametrize("shape", ROOF_SHAPES)
def test_every_shape_is_closed_faces_out_and_reaches_its_height(shape):
    mass = one(roof_shape=shape, roof_height=RISE if shape != "flat" else None)
    assert_closed_and_outward(mass, shapely.box(0, 0, 20, 10), smooth=shape in ("dome", "onion", "cone"))
    tris, _ = triangles(mass)
    assert tris[..., 1].max() == pytest.approx(WALL_TOP + (RISE if shape != "flat" else 0.0), abs=1e-4)
    # nothing of the roof dips below the walls' top
    assert roof_points(mass)[:, 1].min() == pytest.approx(WALL_TOP, abs=1e-4)
    if shape in EXPECTED_VOLUME:
        assert volume(tris) == pytest.approx(EXPECTED_VOLUME[shape], rel=1e-6)
    elif shape != "onion":  # the onion bulges out past the walls
        assert 2000.0 < volume(tris) < 2000.0 + 200 * RISE


def ridge(mass):
    """World (x, z) points at the roof's top."""
    points = roof_points(mass)
    return points[np.isclose(points[:, 1], points[:, 1].max(), atol=1e-4)][:, [0, 2]]


def test_gabled_ridge_runs_along_the_longest_side_by_default_and_across_when_tagged():
    along = ridge(one(roof_shape="gabled"))
    assert np.ptp(along[:, 0]) == pytest.approx(20.0) and np.ptp(along[:, 1]) == pytest.approx(0.0, abs=1e-6)
    assert along[0, 1] == pytest.approx(-5.0)  # the middle of the 10 m side, north toward -z
    across = ridge(one(roof_shape="gabled", roof_orientation="across"))
    assert np.ptp(across[:, 1]) == pytest.approx(10.0) and np.ptp(across[:, 0]) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("direction,ridge_axis", [(0.0, 0), (180.0, 0), (90.0, 1), (270.0, 1)])
def test_roof_direction_turns_the_ridge_across_the_faces_direction(direction, ridge_axis):
    points = ridge(one(roof_shape="gabled", roof_direction=direction))
    assert np.ptp(points[:, 1 - ridge_axis]) == pytest.approx(0.0, abs=1e-6)
    assert np.ptp(points[:, ridge_axis]) > 9.9


@pytest.mark.parametrize("direction,low", [(0.0, "north"), (90.0, "east"), (180.0, "south"), (270.0, "west")])
def test_skillion_falls_toward_its_direction(direction, low):
    square = shapely.box(0, 0, 12, 12)
    points = roof_points(one(square, roof_shape="skillion", roof_direction=direction))
    points = np.unique(np.round(points, 6), axis=0)
    lowest = points[np.isclose(points[:, 1], WALL_TOP)][:, [0, 2]].mean(axis=0)
    highest = points[np.isclose(points[:, 1], WALL_TOP + RISE)][:, [0, 2]].mean(axis=0)
    step = lowest - highest  # scene x east, z south
    expected = {"north": (0, -12), "east": (12, 0), "south": (0, 12), "west": (-12, 0)}[low]
    assert np.allclose(step, expected, atol=1e-6)


def test_roof_angle_sets_the_height_from_the_half_width():
    mass = one(roof_shape="gabled", roof_height=None, roof_angle=45.0, height=30.0)
    assert mass.roof.height == pytest.approx(5.0)  # tan 45 x 5 m
    assert mass.wall_top == pytest.approx(25.0)


@pytest.mark.parametrize(
    ("shape", "rise"),
    [
        ("gabled", math.tan(math.radians(30.0)) * 5),  # the default 30 degrees over half the 10 m width
        ("skillion", math.tan(math.radians(30.0)) * 10),  # one slope over the whole width
        ("hipped", math.tan(math.radians(30.0)) * 5),
        ("cone", math.tan(math.radians(60.0)) * 5),  # a steep spire over the half of the shorter side
        ("pyramidal", math.tan(math.radians(45.0)) * 5),
        ("dome", 5.0),  # as high as its radius
        ("onion", 1.6 * 5),
    ],
)
def test_untagged_roofs_rise_by_their_shapes_pitch(shape, rise):
    mass = one(roof_shape=shape, roof_height=None, height=30.0)
    assert mass.roof.height == pytest.approx(rise)


def test_roof_levels_set_the_height_from_the_storey():
    mass = one(roof_shape="hipped", roof_height=None, roof_levels=1.0, height=15.0, kind="apartments")
    assert mass.roof.height == pytest.approx(3.0)


def test_roof_height_never_takes_the_whole_wall():
    mass = one(roof_shape="gabled", roof_height=40.0, height=12.0)
    assert mass.wall_top == pytest.approx(0.5)


def test_gable_ends_are_walls_and_the_slopes_are_roof():
    mass = one(roof_shape="gabled")
    v = building_vertices(mass, 0)
    walls = v[v["ids"][:, 1] != SURFACE_ROOF]
    above = walls[walls["position"][:, 1] > WALL_TOP + 1e-6]
    assert len(above) and np.allclose(np.abs(above["normal"][:, 0]), 1.0)  # the two east and west gables
    roof = v[v["ids"][:, 1] == SURFACE_ROOF]
    assert np.all(roof["normal"][:, 1] > 0.5)


def test_half_hipped_gables_stop_below_the_ridge():
    mass = one(roof_shape="half-hipped")
    v = building_vertices(mass, 0)
    walls = v[v["ids"][:, 1] != SURFACE_ROOF]
    assert walls["position"][:, 1].max() == pytest.approx(WALL_TOP + 0.6 * RISE)


L_SHAPE = shapely.Polygon([(0, 0), (20, 0), (20, 8), (8, 8), (8, 20), (0, 20)])


@pytest.mark.parametrize("shape", ["hipped", "gabled"])
def test_l_shaped_outlines_follow_the_straight_skeleton(shape):
    mass = one(L_SHAPE, roof_shape=shape)
    assert_closed_and_outward(mass, L_SHAPE)
    points = ridge(mass)
    # a bounding-box roof would put its top over the empty corner (14, -14); the skeleton keeps it
    # inside the outline's wings
    assert all(L_SHAPE.buffer(1e-6).contains(shapely.Point(x, -z)) for x, z in points)
    tris, _ = triangles(mass)
    hipped = volume(triangles(one(L_SHAPE, roof_shape="hipped"))[0])
    if shape == "gabled":
        assert volume(tris) > hipped + 1.0  # the wings end in upright gables
    else:
        # hipped over two 8 m wings: the top is 4 m over the wings' centre lines
        assert {tuple(np.round(p, 3)) for p in points} <= {(4.0, -4.0), (4.0, -16.0), (16.0, -4.0)}


def courtyard():
    return shapely.Polygon([(0, 0), (30, 0), (30, 20), (0, 20)], [[(10, 5), (20, 5), (20, 15), (10, 15)]])


@pytest.mark.parametrize("shape", ["flat", "hipped", "mansard"])
def test_courtyards_have_walls_facing_in_and_roofs_with_a_hole(shape):
    mass = one(courtyard(), roof_shape=shape)
    tris, normals = triangles(mass)
    assert np.allclose(closure(tris), [0.0, 500.0, 0.0], atol=1e-3)
    roof = roof_points(mass)
    inside = (roof[:, 0] > 10 + 1e-6) & (roof[:, 0] < 20 - 1e-6) & (-roof[:, 2] > 5 + 1e-6) & (-roof[:, 2] < 15 - 1e-6)
    assert not inside.any(), "no roof over the courtyard"
    centres = tris.mean(axis=1)
    courtyard_walls = (
        (np.abs(normals[:, 1]) < 1e-6)
        & (np.abs(centres[:, 0] - 15) <= 5 + 1e-6)
        & (np.abs(-centres[:, 2] - 10) <= 5 + 1e-6)
    )
    towards = np.einsum(
        "ij,ij->i", np.array([15.0, -10.0]) - centres[courtyard_walls][:, [0, 2]], normals[courtyard_walls][:, [0, 2]]
    )
    assert courtyard_walls.sum() >= 8 and np.all(towards > 0)


def test_floating_parts_have_an_underside_and_no_wall_below_min_height():
    mass = one(shapely.box(0, 0, 10, 10), height=12.0, min_height=6.0)
    tris, normals = triangles(mass)
    assert tris[..., 1].min() == pytest.approx(6.0)
    under = normals[:, 1] < -0.99
    assert np.all(np.isclose(tris[under][..., 1], 6.0)) and area_vectors(tris[under])[:, 1].sum() == pytest.approx(
        -100.0
    )
    assert np.allclose(closure(tris), 0.0, atol=1e-6)  # closed all round
    assert volume(tris) == pytest.approx(600.0)


@pytest.mark.parametrize("min_height", [None, 0.0])
def test_building_roof_is_a_canopy_with_a_roof_and_no_walls(min_height):
    mass = one(shapely.box(0, 0, 10, 6), kind="roof", has_walls=False, height=4.0, min_height=min_height)
    tris, normals = triangles(mass)
    assert not np.any(np.abs(normals[:, 1]) < 0.5), "no walls"
    assert np.allclose(tris[..., 1], 4.0)  # a roof and its underside, up where the roof is
    assert (
        area_vectors(tris)[:, 1].sum() == pytest.approx(0.0) and (normals[:, 1] > 0).sum() == (normals[:, 1] < 0).sum()
    )


def test_a_pitched_canopy_keeps_its_eaves_above_head_height():
    mass = one(shapely.box(0, 0, 10, 6), kind="roof", has_walls=False, height=5.0, roof_shape="gabled", roof_height=4.0)
    tris, normals = triangles(mass)
    assert tris[..., 1].min() == pytest.approx(2.5) and tris[..., 1].max() == pytest.approx(5.0)
    assert (normals[:, 1] < -0.99).sum() > 0  # the underside under the eaves


def test_outlines_replaced_by_parts_are_not_drawn_and_parts_are():
    outline = MapBuilding(0, "way/1", shapely.box(0, 0, 20, 20), height=10.0, replaced_by_parts=True)
    parts = [
        MapBuilding(1, "way/2", shapely.box(0, 0, 10, 20), height=10.0, is_part=True, parent=0),
        MapBuilding(
            2,
            "way/3",
            shapely.box(10, 0, 20, 20),
            height=25.0,
            is_part=True,
            parent=0,
            roof_shape="dome",
            roof_height=5.0,
        ),
    ]
    masses = masses_of(outline, *parts)
    assert sorted(m.height for m in masses) == [10.0, 25.0]
    assert [m.seed for m in masses] == [1, 2]


def test_colours_and_materials_reach_the_building_record():
    mass = one(roof_shape="gabled", building_colour=(1.0, 0.0, 0.0), roof_material="copper", building_material="brick")
    record = building_record(mass)
    assert np.allclose(record["tint"], [1.0, 0.0, 0.0, 1.0])
    assert record["roof"][3] == 4  # ROOF_COPPER
    assert record["roof"][1] > record["roof"][0]  # weathered green
    tagged = building_record(one(roof_colour=(0.0, 0.0, 1.0), roof_material="roof_tiles", building_material="brick"))
    assert np.allclose(tagged["roof"], [0.0, 0.0, 1.0, 1.0])
    assert tagged["tint"][3] == 1.0 and tagged["tint"][0] > tagged["tint"][2]  # brick red
    plain = building_record(one())
    assert plain["tint"][3] == 0.0  # the style's own tint


@pytest.mark.parametrize(
    "use,kind,grammar",
    [
        ("residential", "apartments", None),
        ("office", "office", "office"),
        ("retail", "retail", "shops"),
        ("industrial", "warehouse", "brick"),
        ("school", "school", "classical"),
        ("church", "church", "classical"),
        (None, "house", "brick"),
    ],
)
def test_facade_style_by_use(use, kind, grammar):
    """The style a use picks is the facade the registry draws: no glass offices on houses."""
    from cityshade.grammar import BUILDING_STYLES

    style = facade_style(MapBuilding(3, "way/1", shapely.box(0, 0, 1, 1), kind=kind, use=use))
    assert BUILDING_STYLES.get(style) == grammar


def test_object_space_turns_with_the_outline():
    turned = shapely.affinity.rotate(shapely.box(0, 0, 30, 10), 30, origin=(0, 0))
    mass = one(turned, roof_shape="gabled")
    assert math.degrees(mass.yaw) % 180 == pytest.approx(30.0, abs=1e-6) or math.degrees(
        -mass.yaw
    ) % 180 == pytest.approx(150.0, abs=1e-6)
    assert_closed_and_outward(mass, turned)
    points = ridge(mass)
    direction = points.max(axis=0) - points.min(axis=0)
    # the ridge follows the long side: 30 degrees north of east is (cos 30, -sin 30) in scene x, z
    assert abs(direction[1] / direction[0]) == pytest.approx(math.tan(math.radians(30)), rel=1e-6)


def roof_gallery():
    """One building per roof shape in two rows, each with its own roof material."""
    materials = [
        "roofing_felt",
        "roof_tiles",
        "slate",
        "copper",
        "metal",
        "roof_tiles",
        "metal",
        "slate",
        "copper",
        "metal",
        "glass",
        "roof_tiles",
        "wood",
    ]
    buildings = []
    for i, shape in enumerate(ROOF_SHAPES):
        x, y = (i % 7) * 26.0, -(i // 7) * 28.0
        round_outline = shape in ("dome", "onion", "cone")
        outline = shapely.Point(x + 9, y + 6).buffer(8, 12) if round_outline else shapely.box(x, y, x + 18, y + 12)
        buildings.append(
            MapBuilding(
                i,
                f"way/{i}",
                outline,
                height=9.0 if shape == "flat" else 14.0,
                levels=3,
                roof_shape=shape,
                roof_height=None if shape in ("dome", "onion") else 5.0,
                roof_material=materials[i],
                building_material="plaster",
            )
        )
    # a third row: the skeleton roofs over an L, a courtyard block, and a bridge between two houses
    skeletons = [
        (shapely.affinity.translate(L_SHAPE, 0, -62), "gabled"),
        (shapely.affinity.translate(L_SHAPE, 30, -62), "hipped"),
        (shapely.affinity.translate(courtyard(), 60, -62), "mansard"),
        (shapely.affinity.translate(L_SHAPE, 100, -62), "gambrel"),
    ]
    for outline, shape in skeletons:
        buildings.append(
            MapBuilding(
                len(buildings),
                f"way/{len(buildings)}",
                outline,
                height=15.0,
                levels=3,
                roof_shape=shape,
                roof_height=4.0,
                roof_material="roof_tiles",
                building_colour=(0.85, 0.8, 0.6),
            )
        )
    buildings += [
        MapBuilding(len(buildings), "way/b1", shapely.box(130, -62, 140, -42), height=12.0),
        MapBuilding(len(buildings) + 1, "way/b2", shapely.box(156, -62, 166, -42), height=12.0),
        MapBuilding(
            len(buildings) + 2,
            "way/bridge",
            shapely.box(140, -56, 156, -50),
            height=11.0,
            min_height=7.0,
            building_colour=(0.5, 0.6, 0.75),
        ),
    ]
    return masses_of(*buildings)


def test_roof_gallery_picture(gl_context, output_dir):
    """All 13 shapes side by side from the air, then skeleton roofs over an L and a courtyard and a
    bridge floating between two houses, in daylight (tests/output/roof_shapes.png): every building
    shows in the id pass."""
    from PIL import Image

    from cityshade.render import Renderer, RenderSettings
    from cityshade.scene import Camera, City

    masses = roof_gallery()
    city = City("roofs", 0, masses, [], (-20.0, -10.0, 190.0, 90.0))
    camera = Camera((84.0, 70.0, 118.0), (84.0, 0.0, 42.0), fov_y=62.0)
    renderer = Renderer((960, 600), RenderSettings(time_of_day=11.0, trees=False, god_rays=False), ctx=gl_context)
    renderer.set_city(city)
    try:
        image = renderer.render(camera)
        ids = renderer.render_ids(camera)
    finally:
        renderer.release()
    Image.fromarray(image).save(output_dir / "roof_shapes.png")
    seen = set(np.unique(ids[..., 2]).tolist()) - {0}
    assert seen == set(range(1, len(masses) + 1))


@pytest.mark.parametrize("shape", ["mansard", "gambrel"])
def test_mansard_and_gambrel_over_any_outline_break_their_pitch_at_the_knee(shape):
    mass = one(L_SHAPE, roof_shape=shape)
    assert_closed_and_outward(mass, L_SHAPE)
    roof = roof_points(mass)
    heights = np.unique(np.round(roof[:, 1] - WALL_TOP, 6))
    knee = {"mansard": 0.75, "gambrel": 0.6}[shape] * RISE
    assert heights.min() == 0.0 and heights.max() == pytest.approx(RISE) and np.isclose(heights, knee).any()
    _, normals = triangles(mass, SURFACE_ROOF)
    slopes = np.unique(np.round(np.degrees(np.arccos(np.clip(normals[:, 1], -1, 1))), 3))
    assert len(slopes) == 2  # a steep lower and a shallow upper pitch


PROBE = (64, 48)
PROBE_COLOUR = (0.7, 0.45, 0.3)  # the roof record's linear colour


@pytest.mark.parametrize("part,material", [(ROOF_PART_SURFACE, m) for m in range(10)] + [(ROOF_PART_SHEET, 1)])
def test_roof_pattern_on_the_gpu_matches_its_numpy_twin(gl_context, part, material):
    """Per-pixel roof albedo (the part's colour times its pattern) and reflectance over a grid of
    points on a flat and two sloped roofs, for every material of the roof's own surface and for
    the sheet metal of rooftop units and dormer cheeks (whatever the roof's material): the GPU and
    numpy agree within 1e-4 except where a pixel sits on a course or tile boundary (float32
    rounding on either side), which may differ on at most 0.5% of the pixels."""
    import moderngl

    from cityshade.gl import ProgramCache, RenderTarget
    from cityshade.scene.testing import roof_part_material, roof_pattern

    program = ProgramCache(gl_context).get("city/roof_probe.glsl")
    target = RenderTarget(gl_context, PROBE, colors=(("f4", 4),))
    vao = gl_context.vertex_array(program, [])
    step, origin = 0.037, (-0.6, 0.35)
    xs, zs = np.meshgrid(origin[0] + step * np.arange(PROBE[0]), origin[1] + step * np.arange(PROBE[1]))
    local = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    try:
        for normal in ((0.0, 1.0, 0.0), (0.0, 0.8, 0.6), (-0.5, 0.7071, 0.5)):
            normal = tuple(np.asarray(normal) / np.linalg.norm(normal))
            program["u_material"] = material
            program["u_part"] = part
            program["u_colour"] = PROBE_COLOUR
            program["u_normal"] = normal
            program["u_origin"] = origin
            program["u_step"] = step
            target.use()
            gl_context.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)  # whatever drew before
            vao.render(vertices=3)
            gpu = target.read(0)[::-1].reshape(-1, 4)  # read() is top row first
            albedo, pattern = roof_part_material(part, (*PROBE_COLOUR, material))
            reference = roof_pattern(pattern, local.astype(np.float32), np.float32(normal))
            reference[:, :3] *= albedo
            differs = np.abs(gpu - reference).max(axis=1) > 1e-4
            print(f"part {part}, material {material}, normal {normal}: {differs.sum()} of {len(differs)} differ")
            assert differs.mean() <= 0.005, (
                f"part {part}, material {material}, normal {normal}: {differs.sum()} of {len(differs)} pixels differ"
            )
    finally:
        vao.release()
        target.release()


def test_a_guessed_direction_leaves_the_ridge_to_the_orientation():
    building = MapBuilding(
        0,
        "way/1",
        shapely.box(0, 0, 20, 10),
        height=14.0,
        roof_shape="gabled",
        roof_height=RISE,
        roof_direction=90.0,
        roof_orientation="along",
        guessed={"roof_direction", "roof_orientation"},
    )
    (mass,) = masses_of(building)
    points = ridge(mass)
    assert np.ptp(points[:, 0]) == pytest.approx(20.0) and np.ptp(points[:, 1]) == pytest.approx(0.0, abs=1e-6)


def test_flat_roofs_of_blocks_sit_inside_a_parapet():
    """A block of three storeys or more: the walls run on PARAPET above its flat roof, whose rim is
    PARAPET_THICKNESS wide with faces looking in; still closed, and the roof's volume is gone."""
    from cityshade.maps.testing import PARAPET
    from cityshade.scene.testing import PARAPET_THICKNESS

    outline = shapely.box(0, 0, 20, 10)
    mass = one(levels=3)
    assert mass.roof.parapet == PARAPET and one(levels=2).roof.parapet == 0.0
    tris, normals = triangles(mass)
    area = area_vectors(tris)
    assert np.allclose(closure(tris), [0.0, outline.area, 0.0], atol=1e-3)
    assert np.all(np.einsum("ij,ij->i", area / np.linalg.norm(area, axis=1)[:, None], normals) > 0.999)
    inner = outline.buffer(-PARAPET_THICKNESS, join_style="mitre")
    units, _ = triangles(mass, SURFACE_ROOF, ROOF_PART_SHEET)  # closed boxes standing on the roof
    assert volume(tris) == pytest.approx(2000.0 - PARAPET * inner.area + volume(units), rel=1e-6)
    roof, roof_normals = triangles(mass, SURFACE_ROOF, ROOF_PART_SURFACE)
    assert roof[..., 1].max() == pytest.approx(WALL_TOP) and roof[..., 1].min() == pytest.approx(WALL_TOP - PARAPET)
    facing = np.abs(roof_normals[:, 1]) < 1e-6  # the rim's inner faces: their fronts look into the roof
    centres = roof[facing].mean(axis=1)[:, [0, 2]] + 0.1 * roof_normals[facing][:, [0, 2]]
    assert facing.sum() == 8 and shapely.contains_xy(inner, *(centres * [1.0, -1.0]).T).all()
