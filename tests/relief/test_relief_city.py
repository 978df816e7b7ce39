"""Relief in the city: the repeating window bay traced on the GPU matches the reference on the
repeated maps, a share of the default city's buildings gets relief facades, the rooms behind a
relief building's glass match the interior twin traced through the reference relief, and the
fly-over's chunk culling keeps its picture."""

import numpy as np
import pytest
from PIL import Image

from cityshade import assets
from cityshade.assets import LABELS
from cityshade.bench.relief import CityChunks, city_frames, flyover_camera
from cityshade.gl import programs as gl_programs
from cityshade.grammar import BUILDING_STYLES, library_texture
from cityshade.interior import GrammarFacades, reference_ids
from cityshade.interior.testing import FACE_CEILING, FACE_CURTAIN, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z
from cityshade.relief import (
    FACADE_RELIEF,
    RELIEF_SHAPES,
    RELIEF_STYLES,
    DetailMaps,
    FacadeView,
    GpuFacade,
    compress,
    draw_facades,
    facade_camera,
    generate_bay,
    paper_facade,
    relief_atlas,
    slab_faces,
    trace_view,
)
from cityshade.relief.testing import MISS, SINGLE_FACADE
from cityshade.render import Renderer, RenderSettings, assign_facades, choose_facade
from cityshade.render.testing import GROUND_MARGIN
from cityshade.scene import Camera, City, batch, box, default_city
from render_checks import hit_edges, id_edges, interior_params, render_finite, style_min_width

SIZE = (96, 96)
BUILDING_NUMBER = {name: number for number, name in BUILDING_STYLES.items()}
ROOM_FACES = [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z, FACE_FURNITURE, FACE_CURTAIN]


def test_repeated_bay_matches_reference(gl_context):
    ctx = gl_context
    programs = gl_programs(ctx)
    bay = generate_bay(texel=0.1)
    wall = DetailMaps(np.tile(bay.depth, (2, 3)), np.tile(bay.material, (2, 3)), bay.texel, bay.depth_unit)
    gpu = GpuFacade(ctx, bay, {"bmf": compress(bay, "bmf")})
    camera = facade_camera(wall, 35, 15, 6.0)
    view = FacadeView(ctx, SIZE, programs)
    view.target.use()
    ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    rows, cols = wall.shape
    draw_facades(
        ctx,
        programs,
        gpu,
        camera,
        "bcfdm",
        slab_faces(cols, rows, gpu.slab_depth, sides=False),
        SINGLE_FACADE,
        1.0,
        tiled=True,
    )
    out, ref = view.read(), trace_view(wall, camera, SIZE)
    # Away from the wall's border (where the repeat goes on but the reference's maps end)...
    x, y = ref.point[..., 0], ref.point[..., 1]
    inner = (ref.material != MISS) & (x > 2) & (x < cols - 2) & (y > 2) & (y < rows - 2)
    assert inner.mean() > 0.5
    differ = inner & ((out.material != ref.material) | (out.face != ref.face))
    print(f"repeated bay: {differ.sum()} of {inner.sum()} inner pixels differ")
    assert not (differ & ~hit_edges(ref)).any(), "pixels differ away from any edge of the reference's picture"
    view.release()
    gpu.release()


def test_an_eighth_of_the_box_buildings_gets_the_relief_bay():
    city = default_city()
    _, records = batch(city.masses)
    count = assign_facades(records, city.masses)["relief bay"]
    marked = np.flatnonzero(records["facade"][:, 0] == FACADE_RELIEF)
    boxes = [i for i, m in enumerate(city.masses) if m.shape in RELIEF_SHAPES]
    due = [i for i in boxes if city.masses[i].style in RELIEF_STYLES]
    assert count == len(marked) and list(marked) == due  # every box building of a relief style, nothing else
    print(f"relief on {count} of {len(boxes)} box buildings ({count / len(boxes):.3f})")
    assert 0.07 < count / len(boxes) < 0.19  # styles are uniform over 0..7: one of eight (style 2)


def test_flyover_chunk_culling_keeps_the_picture(gl_context):
    """`bench relief` Table 3 draws only the chunks inside the frustum: the same picture, fewer facades."""
    ctx = gl_context
    programs = gl_programs(ctx)
    maps = paper_facade("F1")
    gpu = GpuFacade(ctx, maps, {"bmf": compress(maps, "bmf")})
    width, height = maps.size_m
    buildings, size = 400, (128, 96)
    frames = city_frames(buildings, width, width + 8.0)
    chunks = CityChunks(buildings, width, width + 8.0, height, side=4)
    camera = flyover_camera(20 * (width + 8.0), 5)
    view = FacadeView(ctx, size, programs)
    quad = slab_faces(maps.shape[1], maps.shape[0], gpu.slab_depth, sides=False)
    pictures, drawn = [], []
    for shown in (frames, chunks.visible(frames, camera.view_projection(size[0] / size[1]))):
        view.target.use()
        ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        draw_facades(ctx, programs, gpu, camera, "bcfdm", quad, shown, size[0] / size[1])
        pictures.append(view.read())
        drawn.append(len(shown))
    print(f"chunk culling drew {drawn[1]} of {drawn[0]} facades")
    assert drawn[1] < 0.9 * drawn[0]
    assert (pictures[0].material != MISS).mean() > 0.2
    assert np.array_equal(pictures[0].material, pictures[1].material) and np.array_equal(
        pictures[0].face, pictures[1].face
    )
    view.release()
    gpu.release()


RELIEF_STREET = City(
    "relief street",
    0,
    [
        box((0.0, 0.0), 18.0, 12.0, 16.0, style=2, seed=21, room_width=4.5, floor_height=3.2),  # relief
        box((24.0, 0.0), 12.0, 12.0, 16.0, seed=22, room_width=4.0),  # window bay
    ],
    [],
    (-30.0, -30.0, 50.0, 30.0),
    {
        "oblique": Camera((-3.0, 5.5, -9.0), (12.0, 7.0, 2.0), fov_y=60.0),
        "grazing": Camera((-4.0, 2.0, -3.0), (18.0, 6.0, -0.5), fov_y=50.0),
    },
)
CITY_SIZE = (160, 120)


@pytest.mark.parametrize("view", sorted(RELIEF_STREET.viewpoints))
def test_city_relief_glass_leads_into_the_rooms_as_the_twin_says(gl_context, view, output_dir):
    """Behind a relief facade's glass the rooms continue from where the ray meets the recessed
    pane: the id AOV (face, room, building, light and variant) against the interior twin with the
    reference relief tracer (cityshade.interior.reference_ids with `relief`)."""
    renderer = Renderer(CITY_SIZE, RenderSettings(lights=0.6, animation_time=1.3), ctx=gl_context)
    renderer.set_city(RELIEF_STREET)
    assert renderer.city.facades["relief bay"] == 1
    camera = RELIEF_STREET.viewpoints[view]
    gpu = renderer.render_ids(camera, room_state=True)
    colour = render_finite(renderer, camera)
    params = interior_params(renderer)
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    x0, z0, x1, z1 = RELIEF_STREET.bounds
    ground = (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN)
    ref = reference_ids(
        RELIEF_STREET.masses,
        camera,
        CITY_SIZE,
        params,
        alpha,
        ground,
        relief={0: generate_bay()},
        window_bay_relief=relief_atlas(),  # the window-bay building's windows too, near the eye
    )
    flat = reference_ids(RELIEF_STREET.masses, camera, CITY_SIZE, params, alpha, ground)  # glass by the wall point
    renderer.release()
    Image.fromarray(colour).save(output_dir / f"relief_city_{view}.png")
    on_relief = (gpu[..., 2] == 1) | (ref[..., 2] == 1)
    rooms = np.isin(ref[..., 0], ROOM_FACES) & (ref[..., 2] == 1)
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    state_differ = ~differ & (gpu[..., 3] != ref[..., 3])
    moved = rooms & np.any(ref[..., :2] != flat[..., :2], axis=-1)  # what the recess changes
    print(
        f"{view}: {(differ & on_relief).sum()} of {on_relief.sum()} relief-building pixels differ "
        f"({(differ & ~on_relief).sum()} elsewhere), {state_differ.sum()} differ in light or variant; "
        f"{rooms.sum()} room pixels through relief glass, {moved.sum()} of them another face or room than "
        f"at the wall point"
    )
    assert rooms.sum() > 300, "the view must look through relief glass into rooms"
    assert moved.sum() > 0.05 * rooms.sum(), "the view must show rooms entered from the recessed pane"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert (differ & on_relief).sum() <= 0.005 * on_relief.sum()
    assert not state_differ.any()


GRAMMAR_STREET = City(
    "grammar relief street",
    0,
    [
        box((0.0, 0.0), 18.0, 12.0, 16.0, style=BUILDING_NUMBER["classical"], seed=31),
        box((22.0, 0.0), 15.0, 12.0, 19.0, style=BUILDING_NUMBER["office"], seed=32),
    ],
    [],
    (-30.0, -30.0, 50.0, 30.0),
    {
        "oblique": Camera((-3.0, 5.5, -9.0), (12.0, 7.0, 2.0), fov_y=60.0),
        "along": Camera((-4.0, 3.0, -3.5), (30.0, 7.0, -0.5), fov_y=55.0),
    },
)


def grammar_twin(city: City, camera: Camera, params, relief, labels: bool, switch_m: float | None) -> np.ndarray:
    """The interior twin of a city of grammar buildings (reference_ids with their grammars): the id AOV
    with room state, or with `labels` the grammar labels; `relief` the atlas (None: flat windows)."""
    masses = city.masses
    _, records = batch(masses)
    assign_facades(records, masses)
    starts = {i: int(r["facade"][1]) for i, r in enumerate(records)}
    widths = {i: style_min_width(choose_facade(m).grammar_style) for i, m in enumerate(masses)}
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    x0, z0, x1, z1 = city.bounds
    ground = (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN)
    grammar = GrammarFacades(library_texture(), assets.tile_array(), starts, widths, relief, switch_m)
    return reference_ids(masses, camera, CITY_SIZE, params, alpha, ground, grammar=grammar, labels=labels)


@pytest.mark.parametrize("view, switch_m", [("along", 60.0), ("oblique", 60.0), ("oblique", 14.0), ("oblique", None)])
def test_grammar_windows_recessed_as_the_twin_says(gl_context, view, switch_m, output_dir):
    """Grammar facades with recessed windows (each style's openings, cityshade.relief.relief_atlas):
    face, room, building, light, variant and grammar label of the GPU's id AOV against the interior
    twin that traces the same openings with the reference tracer nearer than the switch distance
    and keeps the flat grammar beyond; and the recess matters (the twin without relief differs on a
    share of the window pixels). At 14 m the view holds both: traced near, flat far; None is the
    renderer's default, relief.switch_distance of the view."""
    settings = RenderSettings(lights=0.6, animation_time=1.3, relief_range=switch_m)
    renderer = Renderer(CITY_SIZE, settings, ctx=gl_context)
    renderer.set_city(GRAMMAR_STREET)
    camera = GRAMMAR_STREET.viewpoints[view]
    gpu = renderer.render_ids(camera, room_state=True)
    gpu_labels = renderer.render_ids(camera)[..., 3]
    colour = render_finite(renderer, camera)
    params = interior_params(renderer)
    renderer.release()
    Image.fromarray(colour).save(output_dir / f"relief_grammar_{view}_{switch_m}.png")

    def twin(relief, labels=False, switch=switch_m):
        return grammar_twin(GRAMMAR_STREET, camera, params, relief, labels, switch)

    ref, flat, ref_labels = twin(relief_atlas()), twin(None), twin(relief_atlas(), True)[..., 3]
    if switch_m == 14.0:  # the switch falls inside the view: some windows traced, some flat
        farther = twin(relief_atlas(), switch=60.0)
        assert np.any(ref[..., :2] != flat[..., :2]) and np.any(ref[..., :2] != farther[..., :2])
    buildings = ref[..., 2] > 0
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    state_differ = ~differ & (gpu[..., 3] != ref[..., 3])
    label_differ = ~differ & buildings & (gpu_labels != ref_labels)
    window = buildings & np.isin(ref_labels, [LABELS.index("room"), LABELS.index("window")])
    moved = window & (np.any(ref[..., :2] != flat[..., :2], axis=-1) | (ref_labels != twin(None, True)[..., 3]))
    print(
        f"{view}, switch at {switch_m} m: {differ.sum()} of {buildings.sum()} building pixels differ in face/room/building, "
        f"{state_differ.sum()} in light or variant, {label_differ.sum()} in label; {window.sum()} window pixels, "
        f"{moved.sum()} of them changed by the recess"
    )
    assert window.sum() > 1000, "the view must show grammar windows"
    assert moved.sum() > 0.02 * window.sum(), "the recess must change what the windows show"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert differ.sum() <= 0.001 * differ.size
    assert not state_differ.any()
    assert label_differ.sum() <= 0.001 * label_differ.size


DUSK_STREET = City(
    "dusk relief street",
    0,
    [box((0.0, 0.0), 16.0, 12.0, 13.0, style=BUILDING_NUMBER["dusk"], seed=51)],
    [],
    (-30.0, -30.0, 30.0, 30.0),
    {
        "oblique": Camera((-3.0, 4.5, -6.5), (9.0, 5.5, 1.0), fov_y=60.0),
        "along": Camera((-3.0, 2.5, -2.0), (16.0, 5.0, -0.5), fov_y=55.0),
    },
)


@pytest.mark.parametrize("view, switch_m", [("oblique", None), ("along", 60.0), ("along", 8.0)])
def test_dusk_holes_recessed_as_the_twin_says(gl_context, view, switch_m, output_dir):
    """dusk's windows are holes (SkipMask) through which its own Intrusion rooms show: recessed, each
    hole's opening is stretched over the SkipMask's scope and traced, and through its bottom the
    grammar seen through the hole shows the room from the recessed point. The id AOV (face, room,
    building) and the grammar labels against the interior twin doing the same with the numpy
    evaluator and the reference tracer; through the holes, the grammar's rooms (labels room, or wall
    where a dark room's dim layer wins); and relief on vs off changes only what the twin's recess
    changes, never a frame or the wall: the windows stay in place."""
    settings = RenderSettings(lights=0.6, animation_time=1.3, relief_range=switch_m)
    renderer = Renderer(CITY_SIZE, settings, ctx=gl_context)
    renderer.set_city(DUSK_STREET)
    camera = DUSK_STREET.viewpoints[view]
    gpu = renderer.render_ids(camera)  # face, room, building + 1, grammar label
    Image.fromarray(render_finite(renderer, camera)).save(output_dir / f"relief_dusk_{view}_{switch_m}.png")
    params = interior_params(renderer)
    renderer.release()
    off = Renderer(CITY_SIZE, RenderSettings(lights=0.6, animation_time=1.3, relief=False), ctx=gl_context)
    off.set_city(DUSK_STREET)
    gpu_off = off.render_ids(camera)
    Image.fromarray(render_finite(off, camera)).save(output_dir / f"relief_dusk_{view}_off.png")
    off.release()
    ref = grammar_twin(DUSK_STREET, camera, params, relief_atlas(), True, switch_m)
    flat = grammar_twin(DUSK_STREET, camera, params, None, True, switch_m)
    building = ref[..., 2] == 1
    differ = np.any(gpu != ref, axis=-1)  # face, room, building and label
    room, wall, window = (LABELS.index(name) for name in ("room", "wall", "window"))
    holes = building & np.isin(flat[..., 3], [room, wall])  # what the flat holes show, and the wall
    recess = np.any(ref != flat, axis=-1)
    moved = np.any(gpu != gpu_off, axis=-1)
    print(
        f"{view}, switch at {switch_m} m: {differ.sum()} of {building.sum()} building pixels differ from the twin "
        f"(face, room, building or label); {(flat[..., 3] == room).sum()} flat room pixels, {(ref[..., 3] == room).sum()} "
        f"recessed; the recess "
        f"changes {recess.sum()} (twin), {moved.sum()} (GPU), {(ref[..., 3] == window).sum() - (flat[..., 3] == window).sum()}"
        f" more frame or reveal pixels; relief off against the flat twin: {np.any(gpu_off != flat, axis=-1).sum()} differ"
    )
    assert (building & (flat[..., 3] == room)).sum() > 150, "the view must look into dusk's rooms"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert differ.sum() <= 0.001 * differ.size
    assert not (np.any(gpu_off != flat, axis=-1) & ~id_edges(flat)).any()
    assert (ref[..., 3] == room).sum() > 0.25 * (flat[..., 3] == room).sum(), "the holes still show rooms"
    if switch_m == 8.0:  # the switch inside the view: near holes traced, far ones flat
        farther = grammar_twin(DUSK_STREET, camera, params, relief_atlas(), True, 60.0)
        assert recess.any() and np.any(ref != farther)
    else:
        assert recess.sum() > 0.05 * (building & (flat[..., 3] == room)).sum(), "the recess must show"
    # windows stay in place: relief changes only what the twin's recess changes, inside the holes
    assert not (moved & ~recess & ~id_edges(flat)).any()
    assert not (moved & ~holes & ~id_edges(flat)).any(), "a frame or a pixel off the building moved"


OPENING_FOUND, HOLE_OPENING = 8, 16  # shaders/grammar/building.glsl GRAMMAR_DEFERRED_OPENING, _HOLE_OPENING


@pytest.mark.parametrize("where", ["default close-up", "dusk"])
def test_deferred_openings_draw_what_evaluating_in_place_draws(gl_context, monkeypatch, where, output_dir):
    """The deferred grammar pass passes on the window opening each pixel recesses (its index, scope
    and the flat grammar's colour), so the buildings pass does not evaluate the grammar again for
    the relief. The same frame (4x MSAA) with the deferred pass built without it (RELIEF_OFF there:
    it passes nothing on and the buildings pass evaluates in place, as before) differs only in the
    frame's colour where the flat grammar is no glass: the deferred pass filters the tile over the
    neighbouring pixels' footprint (as its lit colour) and keeps 8 bits; never in where an opening is
    or what it shows. The default city's close-up (its glazed terminals, within a 120 m switch)
    and dusk's holes (what shows through them is still evaluated in the buildings pass)."""
    from cityshade.gl import ProgramCache
    from cityshade.scene import make_city

    if where == "dusk":
        city, camera, size, switch = DUSK_STREET, DUSK_STREET.viewpoints["oblique"], CITY_SIZE, None
    else:
        city = make_city("default")
        camera, size, switch = city.camera("closeup"), (320, 180), 120.0
    get = ProgramCache.get
    frames = {}
    for path in ("deferred", "in place"):

        def built(self, shader, defines=None, varyings=(), path=path):
            if path == "in place" and shader == "grammar/deferred.glsl":
                defines = {**(defines or {}), "RELIEF_OFF": True}
            return get(self, shader, defines, varyings)

        monkeypatch.setattr(ProgramCache, "get", built)
        renderer = Renderer(size, RenderSettings(lights=0.6, animation_time=1.3, relief_range=switch), ctx=gl_context)
        renderer.set_city(city)
        frames[path] = render_finite(renderer, camera).astype(int)
        ids = renderer.targets["grammar result"].read(1)[..., 0]
        renderer.release()
        found = (ids & OPENING_FOUND) != 0
        openings = found & ((ids >> 8 & 0xFF) > 0)
        if path == "deferred":
            holes = openings & ((ids & HOLE_OPENING) != 0)
            print(f"{where}: the deferred pass found {openings.sum()} pixels' openings, {holes.sum()} of them holes'")
            assert openings.sum() > 0.02 * openings.size
            if where == "dusk":
                assert holes.sum() > 0.02 * holes.size
        else:
            assert not found.any(), "built without the openings, the deferred pass passes none on"
    difference = np.abs(frames["deferred"] - frames["in place"]).max(axis=-1)
    Image.fromarray(np.hstack([frames["deferred"], frames["in place"]]).astype(np.uint8)).save(
        output_dir / f"relief_deferred_openings_{where.replace(' ', '_')}.png"
    )
    print(
        f"{where}: {(difference > 0).sum()} of {difference.size} pixels differ, {(difference > 2).sum()} by more "
        f"than 2/255 (at most {difference.max()})"
    )
    assert frames["deferred"].std() > 10, "not an empty picture"
    assert (difference > 0).sum() <= 0.002 * difference.size and difference.max() <= 24


WINDOW_BAY_STREET = City(
    "window bay street",
    0,
    [box((0.0, 0.0), 14.0, 12.0, 16.0, style=0, seed=41, room_width=4.0)],
    [],
    (-30.0, -30.0, 30.0, 30.0),
    {
        "oblique": Camera((-4.0, 4.5, -7.0), (8.0, 6.0, 0.5), fov_y=60.0),
        "along": Camera((-3.0, 2.5, -2.5), (14.0, 6.0, -0.5), fov_y=55.0),
    },
)


@pytest.mark.parametrize("view, switch_m", [("oblique", None), ("along", 60.0), ("along", 8.0)])
def test_window_bay_windows_recessed_as_the_twin_says(gl_context, view, switch_m, output_dir):
    """The plain window bay (style 0) with its window recessed nearer than the switch (the atlas's
    window-bay opening over each bay's glass rectangle): the id AOV (face, room, building, light,
    variant) against the interior twin tracing the same opening; the recess matters; and the
    windows stay in place: with relief off, only pixels on the flat bay's glass change."""
    settings = RenderSettings(lights=0.6, animation_time=1.3, relief_range=switch_m)
    renderer = Renderer(CITY_SIZE, settings, ctx=gl_context)
    renderer.set_city(WINDOW_BAY_STREET)
    assert renderer.city.facades["window bay"] == 1
    camera = WINDOW_BAY_STREET.viewpoints[view]
    gpu = renderer.render_ids(camera, room_state=True)
    Image.fromarray(render_finite(renderer, camera)).save(output_dir / f"relief_window_bay_{view}_{switch_m}.png")
    renderer.release()
    off = Renderer(CITY_SIZE, RenderSettings(lights=0.6, animation_time=1.3, relief=False), ctx=gl_context)
    off.set_city(WINDOW_BAY_STREET)
    gpu_off = off.render_ids(camera, room_state=True)
    off.release()
    params = interior_params(renderer)
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    x0, z0, x1, z1 = WINDOW_BAY_STREET.bounds
    ground = (x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN)
    masses = WINDOW_BAY_STREET.masses
    # the switch as the renderer's: relief_range, else switch_distance of the view (GrammarFacades None)
    grammar = GrammarFacades(library_texture(), assets.tile_array(), {}, {}, None, switch_m)
    ref = reference_ids(
        masses, camera, CITY_SIZE, params, alpha, ground, grammar=grammar, window_bay_relief=relief_atlas()
    )
    flat = reference_ids(masses, camera, CITY_SIZE, params, alpha, ground)
    building = ref[..., 2] == 1
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    state_differ = ~differ & (gpu[..., 3] != ref[..., 3])
    flat_glass = building & np.isin(flat[..., 0], ROOM_FACES)  # rooms seen through the flat bay's glass
    recess = np.any(ref[..., :2] != flat[..., :2], axis=-1)
    off_differ = np.any(gpu_off[..., :3] != flat[..., :3], axis=-1)
    moved = np.any(gpu != gpu_off, axis=-1)
    print(
        f"{view}, switch at {switch_m} m: {differ.sum()} of {building.sum()} building pixels differ from the twin, "
        f"{state_differ.sum()} in light or variant; relief off against the flat twin: {off_differ.sum()} differ; "
        f"{flat_glass.sum()} flat glass pixels, {recess.sum()} changed by the recess (twin), {moved.sum()} (GPU), "
        f"{(moved & ~flat_glass).sum()} of them off the flat glass"
    )
    assert flat_glass.sum() > 500, "the view must show the window bay's glass"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert differ.sum() <= 0.001 * differ.size and not state_differ.any()
    assert not (off_differ & ~id_edges(flat)).any()
    if switch_m == 8.0:  # the switch inside the view: near windows traced, far ones flat
        farther = reference_ids(
            masses,
            camera,
            CITY_SIZE,
            params,
            alpha,
            ground,
            window_bay_relief=relief_atlas(),
            grammar=GrammarFacades(library_texture(), assets.tile_array(), {}, {}, None, 60.0),
        )
        assert recess.any() and np.any(ref[..., :2] != farther[..., :2])
    else:
        assert recess.sum() > 0.05 * flat_glass.sum(), "the recess must change what the windows show"
    # windows stay where they are: relief changes only pixels on the flat bay's glass (or its edge)
    assert not (moved & ~flat_glass & ~id_edges(flat)).any()
