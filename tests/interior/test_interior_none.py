"""Buildings without an interior (sheds, garages, saunas from maps): their glass is a dark pane that
reflects the sky, with no room behind it. GPU id AOV against the numpy twin, and the colour of
those panes, beside a building whose windows open on rooms."""

from __future__ import annotations

import dataclasses

import numpy as np
from PIL import Image

from cityshade.interior import FACE_CODES
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import FLAGS, Camera, City, box
from render_checks import id_edges, interior_twin, render_finite

SIZE = (160, 120)
ROOMS = FLAGS["FLAG_NO_INTERIOR"]
SEEN = 1  # room state bit: a room is seen (cityshade.interior.room_state); room id 0 is a real room
HOUSE = box((0.0, 0.0), 12.0, 10.0, 9.0, seed=3, room_width=4.0, floor_height=3.0)
SHED = box((14.0, 0.0), 8.0, 6.0, 6.0, seed=4, room_width=4.0, floor_height=3.0, interior=False)
BOUNDS = (-30.0, -30.0, 40.0, 30.0)
CAMERA = Camera((11.0, 4.0, -14.0), (11.0, 4.0, 5.0), fov_y=70.0)


def _city(masses) -> City:
    return City("no-interior", 0, masses, [], BOUNDS)


def test_the_flag_is_set_only_without_an_interior():
    assert SHED.flags & ROOMS and not HOUSE.flags & ROOMS


def test_glass_without_an_interior_shows_no_room_on_gpu_and_twin(gl_context, output_dir):
    renderer = Renderer(SIZE, RenderSettings(samples=0, lights=1.0), ctx=gl_context)
    try:
        renderer.set_city(_city([HOUSE, SHED]))
        gpu = renderer.render_ids(CAMERA, room_state=True)
        lit = render_finite(renderer, CAMERA).astype(float).mean(axis=2)
        renderer.set_settings(renderer.settings.with_(lights=0.0))
        dark = render_finite(renderer, CAMERA).astype(float).mean(axis=2)
        renderer.set_settings(renderer.settings.with_(lights=1.0))
        ref = interior_twin(renderer, [HOUSE, SHED], CAMERA, SIZE, BOUNDS)
        # the same shed with rooms: where its glass is (the twin sees rooms there)
        with_rooms = interior_twin(renderer, [HOUSE, dataclasses.replace(SHED, interior=True)], CAMERA, SIZE, BOUNDS)
    finally:
        renderer.release()
    Image.fromarray(lit.astype(np.uint8)).save(output_dir / "interior_none.png")
    edges = id_edges(ref)
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    room_differ = gpu[..., 1] != ref[..., 1]
    house, shed = ref[..., 2] == 1, ref[..., 2] == 2
    house_rooms = house & (ref[..., 3] & SEEN).astype(bool)
    shed_glass = (with_rooms[..., 2] == 2) & (with_rooms[..., 3] & SEEN).astype(bool) & ~id_edges(with_rooms)
    print(
        f"{differ.sum()} of {differ.size} pixels differ in face/room/building ({(differ & ~edges).sum()} away from "
        f"edges), {(room_differ & ~edges).sum()} room ids away from edges; house room pixels "
        f"{house_rooms.sum()}, shed pixels {shed.sum()}, shed glass {shed_glass.sum()}"
    )
    assert not (differ & ~edges).any(), "pixels differ away from any edge of the twin's picture"
    assert not (room_differ & ~edges).any()
    assert (house & (gpu[..., 3] & SEEN).astype(bool)).sum() > 200, "the view must look into the house's rooms"
    assert shed_glass.sum() > 100, "the view must show the shed's windows"
    shed_faces = set(np.unique(gpu[..., 0][gpu[..., 2] == 2]).tolist())
    assert shed_faces <= {FACE_CODES["FACE_EXTERIOR"], FACE_CODES["FACE_ROOF"]}, f"shed faces {shed_faces}"
    assert not (gpu[..., 3][gpu[..., 2] == 2]).any(), "a room seen on the shed"
    # in colour too no room shows behind the shed's panes: lighting every room changes the house's
    # windows, not the shed's
    changed = np.abs(lit - dark) > 2
    house_glass = house_rooms & ~edges
    print(
        f"all lights on vs off: {(changed & house_glass).sum()} of {house_glass.sum()} house glass pixels change, "
        f"{(changed & shed_glass).sum()} of {shed_glass.sum()} shed glass pixels"
    )
    assert (changed & house_glass).sum() > 50
    assert not (changed & shed_glass).any()
