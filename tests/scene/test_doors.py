"""Doors: placing one on a wall, the numpy twin of the shader's door test, and the GPU's id AOV
(door label, no room behind a door) against the twin, on a window-bay and a grammar facade."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade import assets
from cityshade.interior import FACE_CODES, cast_masses
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import DOOR_HEIGHT, DOOR_WIDTH, Camera, City, box, door_hit, door_on_edge
from render_checks import id_edges, interior_twin, render_finite

DOOR_LABEL = assets.LABELS.index("door")


def test_a_door_sits_where_asked_and_moves_only_to_fit_its_wall():
    assert door_on_edge((0, 0), (10, 0), (4, 0.2)) == pytest.approx((4, 0, 0, -1))
    x, z, _, _ = door_on_edge((0, 0), (10, 0), (0.1, 0))
    assert (x, z) == pytest.approx((DOOR_WIDTH / 2, 0)), "kept whole on its wall"
    assert door_on_edge((10, 0), (10, 8), (10, 5)) == pytest.approx((10, 5, 1, 0)), "outward: +x on this side"
    assert door_on_edge((0, 0), (DOOR_WIDTH * 0.9, 0), (0.5, 0)) is None, "a wall narrower than a door"


def test_door_hit_covers_the_door_on_its_wall_only():
    doors = (door_on_edge((0, 0), (10, 0), (9, 0)),)  # on the -z wall, its edge 0.3 m from the corner
    points = np.array(
        [
            [9.0, 1.0, 0.0],
            [9.0, DOOR_HEIGHT + 0.01, 0.0],
            [9.0 + DOOR_WIDTH, 1.0, 0.0],
            [10.0, 1.0, 0.2],
            [8.4, 0.01, 0.0],
        ]
    )
    normals = np.array([[0, 0, -1], [0, 0, -1], [0, 0, -1], [1, 0, 0], [0, 0, -1]], dtype=float)
    hit, uv = door_hit(points, normals, doors)
    x = doors[0][0]
    assert hit.tolist() == [True, False, False, False, True]
    assert uv[0] == pytest.approx([(9.0 - x) / DOOR_WIDTH + 0.5, 1.0 / DOOR_HEIGHT])
    assert not door_hit(points, normals, ())[0].any()


SIZE = (160, 120)
FRONT = box(
    (0.0, 0.0),
    12.0,
    9.0,
    9.0,
    seed=5,
    room_width=4.0,
    floor_height=3.0,
    doors=(door_on_edge((0, 0), (12, 0), (6.0, 0)), door_on_edge((12, 0), (12, 9), (12, 1.0))),
)
SHOPS = box(
    (14.0, 0.0),
    10.0,
    9.0,
    9.0,
    seed=6,
    room_width=4.0,
    floor_height=3.0,
    style=5,
    doors=(door_on_edge((0, 0), (10, 0), (3.0, 0)),),
)
BOUNDS = (-30.0, -30.0, 50.0, 30.0)
CAMERA = Camera((11.0, 2.0, -9.0), (11.0, 1.5, 5.0), fov_y=75.0)


def _twin_doors(masses) -> np.ndarray:
    """Per pixel: the twin's door test on the masses' own solids (building index + 1, 0: no door)."""
    dirs = CAMERA.pixel_rays(SIZE).reshape(-1, 3)
    hits = cast_masses(masses, CAMERA.eye, dirs)
    out = np.zeros(len(dirs), dtype=np.uint32)
    for b, mass in enumerate(masses):
        sel = np.nonzero((hits.building == b) & ~hits.roof)[0]
        out[sel[door_hit(hits.local[sel], hits.normal[sel], mass.doors)[0]]] = b + 1
    return out.reshape(SIZE[1], SIZE[0])


def test_doors_on_gpu_match_the_twin(gl_context, output_dir):
    masses = [FRONT, SHOPS]
    renderer = Renderer(SIZE, RenderSettings(samples=0, lights=0.8, god_rays=False, time_of_day=11.0), ctx=gl_context)
    try:
        renderer.set_city(City("doors", 0, masses, [], BOUNDS))
        labels = renderer.render_ids(CAMERA)
        rooms = renderer.render_ids(CAMERA, room_state=True)
        colour = render_finite(renderer, CAMERA)
    finally:
        renderer.release()
    Image.fromarray(colour).save(output_dir / "doors.png")
    twin_doors = _twin_doors(masses)
    gpu_doors = np.where(labels[..., 3] == DOOR_LABEL, labels[..., 2], 0)
    ref = interior_twin(renderer, masses, CAMERA, SIZE, BOUNDS)
    edges = id_edges(ref) | id_edges(np.stack([twin_doors] * 4, axis=-1))
    differ = gpu_doors != twin_doors
    # the twin knows the window bay's glass, not the grammar's: rooms are compared on the first building
    ids_differ = np.any(rooms[..., :3] != ref[..., :3], axis=-1) & ((ref[..., 2] == 1) | (rooms[..., 2] == 1))
    print(
        f"door pixels: GPU {(gpu_doors > 0).sum()}, twin {(twin_doors > 0).sum()}, {differ.sum()} differ "
        f"({(differ & ~edges).sum()} away from an edge); face/room/building differ on {ids_differ.sum()} pixels"
    )
    for b in (1, 2):
        assert (twin_doors == b).sum() > 150, f"building {b}'s door must be in view"
    assert differ.sum() <= 0.02 * (twin_doors > 0).sum() and not (differ & ~edges).any()
    assert not (ids_differ & ~id_edges(ref)).any() and ids_differ.mean() <= 0.001
    door = twin_doors > 0
    assert (rooms[..., 0][door & ~edges] == FACE_CODES["FACE_EXTERIOR"]).all(), "no room seen through a door"
