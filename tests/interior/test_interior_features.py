"""Interior-mapping features seen in colour: the single atlas, lit rooms, distance LOD, animation."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.interior.testing import FACE_CEILING, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import Camera, City, box
from render_checks import render_finite

SIZE = (192, 144)
MASSES = [box((0.0, 0.0), 24.0, 16.0, 18.0, seed=5, room_width=4.0, floor_height=3.0)]
CAMERA = Camera((10.0, 6.0, -8.0), (12.0, 7.0, 4.0), fov_y=60.0)
ROOM_FACES = [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z]


def _render(ctx, **settings) -> tuple[np.ndarray, np.ndarray]:
    r = Renderer(SIZE, RenderSettings(**{"samples": 0, "lights": 0.5, **settings}), ctx=ctx)
    r.set_city(City("features", 0, MASSES, [], (-40.0, -40.0, 40.0, 40.0)))
    try:
        return render_finite(r, CAMERA).astype(np.float64), r.render_ids(CAMERA)
    finally:
        r.release()


@pytest.mark.slow  # minutes on two cores (make test-slow)
def test_single_atlas_matches_four_textures(gl_context, output_dir):
    four, ids = _render(gl_context)
    atlas, _ = _render(gl_context, single_atlas=True)
    Image.fromarray(np.hstack([four, atlas]).astype(np.uint8)).save(output_dir / "interior_atlas_vs_four.png")
    rooms = np.isin(ids[..., 0], ROOM_FACES)
    assert rooms.sum() > 300
    diff = np.abs(four - atlas).max(axis=-1)[rooms]
    # the same texels through another addressing; mip filtering near tile borders may differ a little
    print(f"atlas vs four textures: mean {diff.mean():.2f}, 95th percentile {np.percentile(diff, 95):.1f} (8-bit)")
    assert diff.mean() < 5 and np.percentile(diff, 95) < 28  # a wrong tile differs by 50+


def test_light_probability_lights_rooms(gl_context):
    dark, ids = _render(gl_context, lights=0.0)
    lit, _ = _render(gl_context, lights=1.0)
    rooms = np.isin(ids[..., 0], ROOM_FACES)
    assert lit[rooms].mean() > 2.5 * dark[rooms].mean()


def test_distance_lod_turns_each_window_into_one_colour(gl_context, output_dir):
    near, ids = _render(gl_context, lod=False)
    far, _ = _render(gl_context, lod=True, lod_range=(0.0, 0.5))
    Image.fromarray(np.hstack([near, far]).astype(np.uint8)).save(output_dir / "interior_lod.png")
    rooms = np.isin(ids[..., 0], ROOM_FACES + [FACE_FURNITURE])
    # keep pixels whose four neighbours see the same room: window edges blend with the frame
    room = ids[..., 1]
    same = np.ones_like(rooms)
    for axis in (0, 1):
        for step in (1, -1):
            same &= np.roll(room, step, axis=axis) == room
    rooms &= same
    spread_near, spread_far = [], []
    for room in np.unique(ids[..., 1][rooms]):
        sel = rooms & (ids[..., 1] == room)
        if sel.sum() >= 12:
            spread_near.append(near[sel].std(axis=0).mean())
            spread_far.append(far[sel].std(axis=0).mean())
    assert len(spread_far) >= 5
    assert np.median(spread_far) < 0.35 * np.median(spread_near)


def test_furniture_sprites_animate(gl_context):
    for t in (0.0, 0.5, 1.0, 1.5):
        frame, ids = _render(gl_context, animation_time=t)
        if t == 0.0:
            first = frame
            continue
        furniture = ids[..., 0] == FACE_FURNITURE
        if furniture.sum() and np.any(np.abs(frame - first)[furniture] > 20):
            return
    pytest.fail("no furniture pixel changed over two seconds of animation")
