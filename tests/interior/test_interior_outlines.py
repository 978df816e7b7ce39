"""Facades and rooms on outlines other than boxes (the `outlines` city: an L-shaped block, a round
tower of 32 short walls, a block round a courtyard and a curved block; the last three with grammar
facades): the GPU's id AOV against the numpy twin, which builds its own solids and evaluates the
grammars with their numpy twin, in the true size of each face. Face, room id and building per
pixel, the room's light and variant, and the grammar label."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.interior import FACE_NAMES, windows_straddling_rooms
from cityshade.interior.testing import FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import Camera, City, cylinder, make_city
from render_checks import grammar_facades, id_edges, interior_twin

SIZE = (160, 120)
MAX_MISMATCH = 0.001  # flat walls: rasterisation edges only
SCENE = make_city("outlines")
MASSES = SCENE.masses
LIT, SEEN = 2, 1


@pytest.fixture(scope="module")
def renderer(gl_context):
    r = Renderer(SIZE, RenderSettings(lights=0.6, animation_time=1.3), ctx=gl_context)
    r.set_city(SCENE)
    yield r
    r.release()


def _grammar(masses=MASSES):
    return grammar_facades(masses)


def _twin_of(renderer, city):
    """twin(camera, labels) -> the twin's id AOV of the renderer's city (room state or grammar labels)."""
    grammar = grammar_facades(city.masses)
    return lambda camera, labels=False: interior_twin(
        renderer, city.masses, camera, SIZE, city.bounds, grammar=grammar, labels=labels
    )


@pytest.fixture(scope="module")
def twin(renderer):
    """twin(view, labels) -> the twin's id AOV (room state or grammar labels), computed once."""
    cache = {}
    of = _twin_of(renderer, SCENE)

    def pixels(view: str, labels: bool = False):
        if (view, labels) not in cache:
            cache[view, labels] = of(SCENE.camera(view), labels)
        return cache[view, labels]

    return pixels


def test_the_scene_has_grammar_and_window_bay_buildings():
    assert len(_grammar().starts) == 3 and 0 not in _grammar().starts


@pytest.mark.parametrize("view", sorted(SCENE.viewpoints))
def test_gpu_ids_match_numpy_twin(renderer, twin, view, output_dir):
    camera = SCENE.camera(view)
    gpu = renderer.render_ids(camera, room_state=True)
    ref = twin(view)
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    rooms = ~differ & (ref[..., 3] & SEEN).astype(bool)
    state_differ = rooms & (gpu[..., 3] != ref[..., 3])
    faces, counts = np.unique(gpu[..., 0], return_counts=True)
    print(
        f"{view}: {differ.sum()} of {differ.size} pixels differ in face/room/building; of {rooms.sum()} room "
        f"pixels {state_differ.sum()} differ in light or variant; faces: "
        + ", ".join(f"{FACE_NAMES[int(f)]}={c}" for f, c in zip(faces, counts))
    )
    palette = ((gpu[..., 1].astype(np.int64) * 2654435761 + gpu[..., 2] * 97) >> 8) & 0xFFFFFF
    Image.fromarray(np.stack([(palette >> s) & 255 for s in (0, 8, 16)], -1).astype(np.uint8)).save(
        output_dir / f"outlines_ids_{view}.png"
    )
    assert differ.mean() <= MAX_MISMATCH, f"{differ.sum()} pixels differ"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert not state_differ.any(), f"{state_differ.sum()} room pixels differ in light or variant"
    assert np.isin(gpu[..., 0], [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z]).sum() > 200


@pytest.mark.parametrize("view", sorted(SCENE.viewpoints))
def test_gpu_grammar_labels_match_numpy_twin(renderer, twin, view):
    """The grammar evaluated in the true size of each face, by the GPU and by the grammar's twin."""
    gpu = renderer.render_ids(SCENE.camera(view))
    ref = twin(view, labels=True)
    grammar = np.isin(ref[..., 2] - 1, list(_grammar().starts)) & (ref[..., 2] > 0)
    same = np.all(gpu[..., :3] == ref[..., :3], axis=-1)
    differ = grammar & same & (gpu[..., 3] != ref[..., 3])
    print(f"{view}: {differ.sum()} of {(grammar & same).sum()} grammar pixels differ in label")
    if view != "l_shape":  # the L-shaped block has window bays: no labels
        assert (grammar & same).sum() > 500
    assert differ.sum() <= MAX_MISMATCH * differ.size


@pytest.mark.parametrize("view", sorted(SCENE.viewpoints))
def test_no_window_shows_two_rooms(renderer, view):
    count = windows_straddling_rooms(renderer.render_ids(SCENE.camera(view), windows=True))
    print(
        f"{view}: {count.windows} windows, {count.straddling} showing two rooms; {count.patches_with_rooms} "
        f"glass patches show several rooms, {count.patches_of_touching_windows} of them touching windows"
    )
    assert count.windows > 10 and count.straddling == 0
    assert count.patches_with_rooms == count.patches_of_touching_windows


def test_a_grammar_cylinder_matches_its_twin(gl_context):
    """A round tower drawn as a cylinder (48 facets on the GPU, the exact circle in the twin) with
    the brick grammar round its whole circumference: ids and labels differ on at most 2% of its
    pixels (the facets' sagitta, as on the window-bay cylinder of test_interior_ids.py)."""
    city = City(
        "round", 0, [cylinder((0.0, 0.0), 18.0, 24.0, seed=5, style=4, room_width=4.0)], [], (-30.0, -30.0, 30.0, 30.0)
    )
    camera = Camera((9.0, 5.0, -14.0), (9.0, 10.0, 9.0), fov_y=70.0)
    r = Renderer(SIZE, RenderSettings(lights=0.6, animation_time=1.3), ctx=gl_context)
    r.set_city(city)
    try:
        gpu, gpu_labels = r.render_ids(camera, room_state=True), r.render_ids(camera)
        windows = windows_straddling_rooms(r.render_ids(camera, windows=True))
        twin = _twin_of(r, city)
        ref, ref_labels = twin(camera), twin(camera, labels=True)
    finally:
        r.release()
    on = (gpu[..., 2] == 1) | (ref[..., 2] == 1)
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    same = ~differ & (gpu[..., 2] == 1)
    labels = same & (gpu_labels[..., 3] != ref_labels[..., 3])
    print(
        f"grammar cylinder: {differ.sum()} of {on.sum()} pixels differ in ids, {labels.sum()} of {same.sum()} "
        f"in label; {windows.windows} windows, {windows.straddling} showing two rooms"
    )
    assert on.sum() > 4000 and differ.sum() <= 0.02 * on.sum() and labels.sum() <= 0.02 * same.sum()
    assert not (differ & ~id_edges(ref)).any()
    assert windows.windows > 20 and windows.straddling == 0
