"""Interior mapping on the GPU against its numpy twin, which builds its own geometry from the
building masses: pixel by pixel through the id AOV (face, room id, building, and the room's light
and texture variant), and room by room (lit or dark, seen in colour). The window bay's windows are
recessed near the eye, as the renderer's default (relief on)."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade import assets
from cityshade.interior import FACE_NAMES, InteriorParams, reference_ids
from cityshade.interior.testing import FACE_CEILING, FACE_CURTAIN, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z
from cityshade.relief import relief_atlas
from cityshade.render import Renderer, RenderSettings
from cityshade.render.testing import GROUND_MARGIN
from cityshade.scene import make_city
from render_checks import id_edges, render_finite

SIZE = (160, 120)
# Flat walls: only rasterisation-edge pixels may differ (share of the picture). Curved walls: the
# GPU draws facets, the twin the exact cylinder or sphere, so silhouettes, window and room edges
# move by up to the facets' sagitta (share of the pixels on curved buildings).
MAX_MISMATCH_FLAT = 0.001
MAX_MISMATCH_CURVED = 0.02
LIT, SEEN = 2, 1  # room state bits (cityshade.interior.room_state)


SCENE = make_city("interior")
MASSES = SCENE.masses
CAMERAS = SCENE.viewpoints
CURVED = [i + 1 for i, m in enumerate(MASSES) if m.shape != "prism"]  # building + 1, as in the id AOV


@pytest.fixture(scope="module")
def renderer(gl_context):
    r = Renderer(SIZE, RenderSettings(lights=0.6, animation_time=1.3), ctx=gl_context)
    r.set_city(SCENE)
    yield r
    r.release()


@pytest.fixture(scope="module")
def twin(renderer):
    """twin(view) -> the numpy twin's id AOV with room state for a view, computed once per module."""
    cache = {}

    def pixels(view: str):
        if view not in cache:
            alpha = assets.facade_texture()[0][..., 3] / 255.0
            cache[view] = reference_ids(
                MASSES, CAMERAS[view], SIZE, _params(renderer), alpha, _ground(), window_bay_relief=relief_atlas()
            )
        return cache[view]

    return pixels


def _params(renderer) -> InteriorParams:
    sprites = assets.furniture_sprites()
    s = renderer.settings
    return InteriorParams(
        lights=s.lights,
        time=s.animation_time,
        variants=renderer.textures.room_variants,
        glass_rect=renderer.textures.glass_rect,
        sprite_alpha=sprites[..., 3] / 255.0,
    )


def _colorise(ids: np.ndarray) -> np.ndarray:
    palette = np.array(
        [
            [0, 0, 0],
            [150, 150, 150],
            [240, 240, 90],
            [150, 90, 40],
            [90, 160, 240],
            [40, 90, 200],
            [240, 60, 60],
            [220, 120, 220],
            [90, 90, 90],
            [40, 40, 40],
        ],
        dtype=np.uint8,
    )
    room_tint = ((ids[..., 1] * 2654435761) >> 24).astype(np.uint8)[..., None] // 4
    return np.clip(palette[ids[..., 0] % 10].astype(int) + room_tint, 0, 255).astype(np.uint8)


def _ground() -> tuple[float, float, float, float]:
    x0, z0, x1, z1 = SCENE.bounds
    return x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN


@pytest.mark.parametrize("view", sorted(CAMERAS))
def test_gpu_ids_match_numpy_twin(renderer, twin, view, output_dir):
    """Face, room id and building per pixel; then, where both see a room, its light and variant."""
    camera = CAMERAS[view]
    gpu = renderer.render_ids(camera, room_state=True)
    ref = twin(view)
    Image.fromarray(np.hstack([_colorise(gpu), _colorise(ref)])).save(output_dir / f"interior_ids_{view}.png")
    differ = np.any(gpu[..., :3] != ref[..., :3], axis=-1)
    curved = np.isin(gpu[..., 2], CURVED) | np.isin(ref[..., 2], CURVED)
    rooms = ~differ & (ref[..., 3] & SEEN).astype(bool)
    lit_differ = rooms & ((gpu[..., 3] ^ ref[..., 3]) & LIT).astype(bool)
    variant_differ = rooms & ((gpu[..., 3] >> 2) != (ref[..., 3] >> 2))
    flat_share = (differ & ~curved).mean()
    curved_share = (differ & curved).sum() / max(curved.sum(), 1)
    faces, counts = np.unique(gpu[..., 0], return_counts=True)
    print(
        f"{view}: {differ.sum()} of {differ.size} pixels differ in face/room/building: {(differ & ~curved).sum()} "
        f"on flat buildings or the ground, {(differ & curved).sum()} of {curved.sum()} on curved ones ({curved_share:.2%}); "
        f"of {rooms.sum()} room pixels {lit_differ.sum()} differ in light, {variant_differ.sum()} in variant; "
        + "faces: "
        + ", ".join(f"{FACE_NAMES[int(f)]}={c}" for f, c in zip(faces, counts))
    )
    assert flat_share <= MAX_MISMATCH_FLAT, f"{(differ & ~curved).sum()} pixels differ on flat buildings"
    assert curved_share <= MAX_MISMATCH_CURVED, f"{(differ & curved).sum()} pixels differ on curved buildings"
    assert not (differ & ~id_edges(ref)).any(), "pixels differ away from any edge of the twin's picture"
    assert not lit_differ.any(), f"{lit_differ.sum()} room pixels differ in light"
    assert not variant_differ.any(), f"{variant_differ.sum()} room pixels differ in texture variant"
    assert not (~differ & ((gpu[..., 3] ^ ref[..., 3]) & SEEN).astype(bool)).any(), "a room seen by one only"
    interior = np.isin(gpu[..., 0], [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z])
    assert interior.sum() > 200, "the view must look into rooms"
    assert len(np.unique(ref[..., 3][rooms] >> 2)) > 1, "the view must show more than one room variant"


def test_all_interior_faces_appear(renderer):
    seen = set()
    for camera in CAMERAS.values():
        seen |= set(np.unique(renderer.render_ids(camera)[..., 0]).tolist())
    for face in (FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z, FACE_FURNITURE, FACE_CURTAIN):
        assert face in seen, f"no {FACE_NAMES[face]} pixels in any view"


def test_corner_shows_the_same_room_through_both_facades(renderer):
    """Paper: at a corner the same room is seen through both facades (object-space rooms)."""
    ids = renderer.render_ids(CAMERAS["corner"])
    building0 = ids[..., 2] == 1
    interior = np.isin(ids[..., 0], [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z, FACE_FURNITURE])
    alpha = assets.facade_texture()[0][..., 3] / 255.0
    ref = reference_ids(
        MASSES, CAMERAS["corner"], SIZE, _params(renderer), alpha, _ground(), window_bay_relief=relief_atlas()
    )
    assert (ref[..., 1][building0 & interior] == ids[..., 1][building0 & interior]).all()
    # the corner room's id is reached through windows on both the -z facade and the -x facade
    rooms_by_facade = {}
    dirs = CAMERAS["corner"].pixel_rays(SIZE)
    eye = CAMERAS["corner"].eye
    # which facade a pixel entered through: compare the entry plane via the ray's first box hit
    t_front = (0.0 - eye[2]) / dirs[..., 2]
    t_side = (0.0 - eye[0]) / dirs[..., 0]
    entered_front = (t_front > 0) & ((t_side < 0) | (t_front > t_side))
    for name, mask in (("front", entered_front), ("side", ~entered_front)):
        rooms_by_facade[name] = set(ids[..., 1][building0 & interior & mask].tolist())
    assert rooms_by_facade["front"] & rooms_by_facade["side"], "no room is visible through both facades"


@pytest.mark.parametrize("view", sorted(CAMERAS))
def test_lit_rooms_match_numpy_twin(renderer, twin, view):
    """A room the twin calls lit is brighter on the GPU than with every light off (lights = 0),
    and a dark room is unchanged: compared per room seen (building, room id from the id AOV)."""
    camera = CAMERAS[view]
    ids = renderer.render_ids(camera)
    lit_colour = render_finite(renderer, camera).astype(float).mean(axis=2)
    settings = renderer.settings
    renderer.set_settings(settings.with_(lights=0.0))
    dark_colour = render_finite(renderer, camera).astype(float).mean(axis=2)
    renderer.set_settings(settings)
    ref = twin(view)
    ref_lit = (ref[..., 3] & LIT).astype(bool)
    rooms = np.isin(ids[..., 0], [FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z])
    rooms &= np.all(ids[..., :3] == ref[..., :3], axis=-1)
    keys = ids[..., 2].astype(np.int64) << 32 | ids[..., 1].astype(np.int64)
    verdicts = []
    for key in np.unique(keys[rooms]):
        seen = rooms & (keys == key)
        if seen.sum() < 6:
            # a sliver of a room: its median is mostly window edge, or (the dome's windows near its
            # silhouette, 4 pixels each) glass seen so obliquely that it reflects nearly all light
            continue
        gpu_lit = np.median(lit_colour[seen]) > 1.1 * max(np.median(dark_colour[seen]), 1.0)
        verdicts.append((bool(ref_lit[seen].mean() > 0.5), bool(gpu_lit)))
    wrong = sum(twin != gpu for twin, gpu in verdicts)
    print(f"{view}: {wrong} of {len(verdicts)} rooms lit differently; twin lit {sum(t for t, _ in verdicts)}")
    assert wrong == 0
    assert {twin for twin, _ in verdicts} == {True, False}, "the view must show lit and dark rooms"
