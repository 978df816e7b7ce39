"""Grammar facades in the city: buildings pick a library style by their style number, the label
AOV shows the grammar's labels, and glass opens onto interior-mapped rooms."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.assets import LABELS, tile_array
from cityshade.grammar import BUILDING_STYLES, evaluate, facade_seed_vector, library_texture, library_texture_with
from cityshade.interior.testing import FACE_EXTERIOR
from cityshade.render import Renderer, RenderSettings, assign_facades
from cityshade.scene import SURFACE_WALL, USE_CODES, USES, Camera, City, batch, box, dome, dome_faces, make_city
from render_checks import grammar_test_settings, render_finite

SIZE = (128, 96)
STYLE = {name: number for number, name in BUILDING_STYLES.items()}


@pytest.fixture(scope="module")
def renderer(gl_context):
    masses = [
        box((0.0, 0.0), 20.0, 14.0, 19.0, seed=5, style=STYLE["brick"]),
        box((26.0, 0.0), 14.0, 14.0, 19.0, seed=6, style=0),
    ]
    r = Renderer(SIZE, RenderSettings(lights=0.7), ctx=gl_context)
    r.set_city(City("grammar", 0, masses, [], (-40.0, -40.0, 60.0, 60.0)))
    yield r
    r.release()


def test_records_carry_start_rule_and_seed():
    masses = [box((0.0, 0.0), 10.0, 10.0, 9.0, seed=3, style=STYLE["dusk"]), box((20.0, 0.0), 10.0, 10.0, 9.0)]
    _, records = batch(masses)
    assert assign_facades(records, masses)["grammar dusk"] == 1
    assert records["facade"][0, 0] == 1 and records["facade"][0, 1] == library_texture().address("dusk")
    assert not records["facade"][1].any()  # the default style keeps the window bays


def test_records_carry_the_use():
    masses = [box((0.0, 0.0), 10.0, 10.0, 9.0, use=use, furniture=False) for use in USES.values()]
    _, records = batch(masses)
    shift = USE_CODES["USE_SHIFT"]
    assert ((records["ids"][:, 2] >> shift) & USE_CODES["USE_MASK"]).tolist() == list(USES.values())
    assert (records["ids"][:, 2] & 15).tolist() == [masses[0].flags & 15] * len(USES)  # the flags stay
    with pytest.raises(ValueError, match="unknown building use code 9"):
        box((0.0, 0.0), 10.0, 10.0, 9.0, use=9)


def test_label_aov_shows_grammar_labels_and_rooms(renderer, output_dir):
    camera = Camera((10.0, 6.0, -18.0), (16.0, 8.0, 7.0), fov_y=60.0)
    ids = renderer.render_ids(camera)
    colour = render_finite(renderer, camera)
    Image.fromarray(colour).save(output_dir / "grammar_city.png")
    grammar_pixels = ids[..., 2] == 1
    labels = {LABELS[v] for v in np.unique(ids[..., 3][grammar_pixels])}
    assert {"wall", "window", "room", "door"} <= labels
    assert not ids[..., 3][ids[..., 2] == 2].any()  # the window-bay building has no grammar labels
    room = grammar_pixels & (ids[..., 3] == LABELS.index("room"))
    assert room.any() and (ids[..., 0][room] != FACE_EXTERIOR).all()  # behind the glass: interior-mapped faces


def test_default_city_uses_grammar_facades():
    city = make_city("default")
    styles = {m.style for m in city.masses}
    assert len(styles & set(BUILDING_STYLES)) >= 5


PATHS = ("forward", "deferred")


def _grammar_city(gl_context, tmp_path, text: str, masses, path: str, size, **extra) -> Renderer:
    """The city of `masses` drawn by the frame with every grammar facade in grammar `text`
    (compiled after the library through RenderSettings.grammar_files), lit at midday, by `path`."""
    grammar = tmp_path / "city_test.grammar"
    grammar.write_text(text)
    settings = grammar_test_settings(grammar, "city_test", path, samples=0, **extra)
    renderer = Renderer(size, settings, ctx=gl_context)
    renderer.set_city(City("grammar test", 0, masses, [], (-60.0, -60.0, 60.0, 60.0)))
    return renderer


def _city_pixels(renderer, camera, points, name, output_dir):
    """Draws the city; the image (int RGB) and the (row, column) of world points."""
    image = render_finite(renderer, camera).astype(int)
    Image.fromarray(image.astype(np.uint8)).save(output_dir / f"{name}_{renderer.settings.grammar_deferred}.png")
    height, width = image.shape[:2]
    clip = camera.view_projection(width / height) @ np.array([[*p, 1.0] for p in points]).T
    ndc = clip[:2] / clip[3]
    return image, ((1 - ndc[1]) / 2 * height).astype(int), ((ndc[0] + 1) / 2 * width).astype(int)


@pytest.mark.parametrize("path", PATHS)
def test_building_use_and_height_reach_the_conditions_in_the_city(gl_context, tmp_path, path, output_dir):
    """The record's use and height feed building.use / building.height on the GPU, by both paths
    (the deferred pass reads them through the building index in its G-buffer)."""
    text = (
        "S->Case(building.use == use.office, Red, building.height > 30, Green, Yellow)\n"
        "Red->Color(0.9, 0.1, 0.1)\nGreen->Color(0.1, 0.9, 0.1)\nYellow->Color(0.9, 0.9, 0.1)\n"
    )
    office = STYLE["office"]
    masses = [
        box((-25.0, 0.0), 14.0, 14.0, 12.0, use=USES["office"], style=office),
        box((-7.0, 0.0), 14.0, 14.0, 40.0, use=USES["home"], style=office),
        box((11.0, 0.0), 14.0, 14.0, 12.0, style=office),
    ]
    renderer = _grammar_city(gl_context, tmp_path, text, masses, path, (160, 96))
    try:
        camera = Camera((0.0, 10.0, -60.0), (0.0, 8.0, 0.0), fov_y=60.0)
        points = [(x, 5.0, 0.0) for x in (-18.0, 0.0, 18.0)]  # the buildings' fronts
        image, rows, columns = _city_pixels(renderer, camera, points, "grammar_city_uses", output_dir)
        r, g, b = (image[rows, columns, k] for k in range(3))
        assert r[0] > 2 * g[0] and g[1] > 2 * r[1] and r[2] > 2 * b[2] and g[2] > 2 * b[2], (r, g, b)
    finally:
        renderer.release()


@pytest.mark.parametrize("path", (*PATHS, "cached"))
def test_facade_level_reaches_the_conditions_in_the_city(gl_context, tmp_path, path, output_dir):
    """facade.level on the GPU, by both paths and through the deferred path's page cache: 0 on a box
    on the ground, 2 on a box raised two storeys (a building part's first level), and a dome's rings
    0, 1, 2 up its arc."""
    text = (
        "S->Case(facade.level == 0, Red, facade.level == 2, Blue, Green)\n"
        "Red->Color(0.9, 0.1, 0.1)\nGreen->Color(0.1, 0.9, 0.1)\nBlue->Color(0.1, 0.1, 0.9)\n"
    )
    style = STYLE["brick"]
    masses = [
        box((-30.0, 0.0), 14.0, 14.0, 12.0, style=style),
        box((-12.0, 0.0), 14.0, 14.0, 16.0, style=style, base=6.4, first_level=2),
        dome((6.0, 0.0), 30.0, floor_height=3.0, style=style),
    ]
    rings = dome_faces(15.0, 3.0, masses[2].room_width)
    assert rings.walls >= 3
    extra = {"grammar_cache": True} if path == "cached" else {}
    renderer = _grammar_city(
        gl_context, tmp_path, text, masses, "forward" if path == "forward" else "deferred", (200, 120), **extra
    )
    try:
        camera = Camera((-4.0, 8.0, -62.0), (-4.0, 7.0, 0.0), fov_y=60.0)
        lat = rings.lat[:3].mean(axis=1)
        points = [(-23.0, 6.0, 0.0), (-5.0, 11.0, 0.0)]  # the boxes' fronts
        points += [(21.0, 15.0 * np.sin(a), 15.0 - 15.0 * np.cos(a)) for a in lat]  # rings 0, 1, 2 facing the camera
        image, rows, columns = _city_pixels(renderer, camera, points, f"grammar_city_levels_{path}", output_dir)
        rgb = image[rows, columns]
        picked = "".join("RGB"[int(np.argmax(c))] if c.max() > 2 * np.sort(c)[1] else "?" for c in rgb)
        print(f"{path}: levels 0, 2 and rings 0, 1, 2 drawn {picked} ({rgb.tolist()})")
        assert picked == "RBRGB", rgb
        if path == "cached":  # the faces at their building's first level came from the cache's pages
            assert renderer.textures.grammar_pass.cache.stats["resident"] > 0
    finally:
        renderer.release()


@pytest.mark.parametrize("path", PATHS)
def test_the_sides_of_a_city_building_draw_their_own_streams(gl_context, tmp_path, path, output_dir):
    """Two sides of one box pick their bays as the twin does with each facade's own seed
    (grammar.facade_seed_vector of the face's index, its first room column), not with one seed for
    the building."""
    text = "S->RepeatX(2, Bay)\nBay->RandUni(0, Red, Yellow)\nRed->Color(0.9, 0.1, 0.1)\nYellow->Color(0.9, 0.9, 0.1)\n"
    mass = box((0.0, 0.0), 20.0, 20.0, 10.0, seed=7, style=STYLE["office"])
    renderer = _grammar_city(gl_context, tmp_path, text, [mass], path, (240, 160))
    try:
        compiled = library_texture_with(renderer.settings.grammar_files)
        camera = Camera((48.0, 9.0, -28.0), (10.0, 5.0, 10.0), fov_y=55.0)
        centres = np.arange(10) * 2.0 + 1.0
        vertices, _ = batch([mass])
        walls = vertices[vertices["ids"][:, 1] == SURFACE_WALL]

        def face_of(normal):  # the face index (first room column) of the wall facing `normal`
            return int(walls["ids"][np.all(np.isclose(walls["normal"], normal), axis=1), 2][0])

        sides = {
            face_of((0.0, 0.0, -1.0)): [(x, 5.0, 0.0) for x in centres],  # the -z wall
            face_of((1.0, 0.0, 0.0)): [(20.0, 5.0, z) for z in centres],
        }  # the +x wall
        uv = np.stack([centres, np.full(10, 5.0)], axis=1).astype(np.float32)
        seen = {}
        for face, points in sides.items():
            image, rows, columns = _city_pixels(renderer, camera, points, "grammar_city_sides", output_dir)
            yellow = image[rows, columns, 1] > image[rows, columns, 2] + 60  # red or yellow, never unlit
            assert (image[rows, columns, 0] > image[rows, columns, 2] + 60).all(), "a bay centre is not on the wall"
            twin = evaluate(
                compiled, compiled.address("city_test"), uv, (20.0, 10.0), facade_seed_vector(7, face), tile_array(16)
            ).terminal == compiled.address("city_test", "Yellow")
            assert (yellow == twin).all() or (yellow == twin[::-1]).all(), (face, yellow, twin)
            seen[face] = twin
        assert len(seen) == 2 and (seen[min(seen)] != seen[max(seen)]).any()  # the two sides chose differently
    finally:
        renderer.release()
