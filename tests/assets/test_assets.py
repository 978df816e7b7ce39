"""Procedural textures: shapes, conventions, determinism; PNGs under tests/output/assets/."""

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade.assets import (
    FACES,
    SPRITE_KINDS,
    cube_directions,
    curtain_texture,
    environment_cubemap,
    facade_texture,
    furniture_sprites,
    room_atlas,
    room_textures,
    sky_colour,
)
from cityshade.assets._facade import _facade

SUNS = [(-0.55, 0.2, -0.81), (0.3, 0.6, 0.2), (0.9, 0.15, 0.1), (0.0, 0.95, -0.3)]


def save(folder: Path, name: str, image: np.ndarray) -> Path:
    """Write a bottom-row-first image as a PNG the right way up."""
    folder.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.ascontiguousarray(image[::-1])).save(folder / f"{name}.png")
    return folder / f"{name}.png"


def tonemap(radiance: np.ndarray) -> np.ndarray:
    mapped = radiance / (1 + radiance)
    return (np.clip(mapped, 0, 1) ** (1 / 2.2) * 255 + 0.5).astype(np.uint8)


def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


# --------------------------------------------------------------------------- rooms


def test_room_textures_shapes_and_alpha():
    rooms = room_textures(size=64, variants=10, seed=3)
    assert list(rooms) == list(FACES)
    for stack in rooms.values():
        assert stack.shape == (10, 64, 64, 4) and stack.dtype == np.uint8
        assert (stack[..., 3] == 255).all()


def test_room_textures_are_deterministic_and_seeded():
    a = room_textures(size=64, variants=3, seed=1)
    b = room_textures(size=64, variants=2, seed=1)  # computed afresh, not from the cache
    c = room_textures(size=64, variants=2, seed=2)
    for face in FACES:
        assert np.array_equal(a[face][:2], b[face])
        assert not np.array_equal(b[face], c[face])


def test_room_variants_and_wall_orientations_differ():
    rooms = room_textures(size=64)
    walls = rooms["wall_x"].astype(float)
    for i in range(len(walls)):
        for j in range(i + 1, len(walls)):
            assert np.abs(walls[i] - walls[j]).mean() > 8, (i, j)
    for k in range(len(walls)):
        assert np.abs(rooms["wall_x"][k].astype(float) - rooms["wall_z"][k]).mean() > 8, k


def test_walls_have_dark_ceiling_band():
    rooms = room_textures(size=128)
    for face in ("wall_x", "wall_z"):
        walls = luminance(rooms[face][..., :3].astype(float))
        band = walls[:, -4:].mean(axis=(1, 2))
        assert (band < walls.mean(axis=(1, 2))).all()


def test_results_are_read_only():
    with pytest.raises(ValueError):
        room_textures(size=32)["floor"][0, 0, 0, 0] = 1


def test_atlas_layout_round_trips_tiles():
    rooms = room_textures(size=32, variants=5)
    atlas, layout = room_atlas(rooms, padding=3)
    tile, pad = layout["tile"], layout["padding"]
    cell = tile + 2 * pad
    assert (layout["columns"], layout["rows"], layout["face_order"]) == (5, 4, list(FACES))
    assert atlas.shape == (4 * cell, 5 * cell, 4) and atlas.dtype == np.uint8
    for f, face in enumerate(layout["face_order"]):
        for k in range(layout["columns"]):
            x0, y0 = k * cell + pad, f * cell + pad
            assert np.array_equal(atlas[y0 : y0 + tile, x0 : x0 + tile], rooms[face][k])
            padded = atlas[y0 - pad : y0 + tile + pad, x0 - pad : x0 + tile + pad]
            expected = np.pad(rooms[face][k], ((pad, pad), (pad, pad), (0, 0)), mode="edge")
            assert np.array_equal(padded, expected)


# --------------------------------------------------------------------------- facade


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("size", [37, 128])
def test_facade_alpha_is_exactly_the_glass_rectangle(seed, size):
    image, (u0, v0, u1, v1) = facade_texture(size=size, seed=seed)
    assert image.shape == (size, size, 4) and image.dtype == np.uint8
    assert set(np.unique(image[..., 3])) == {0, 255}
    cols = (np.arange(size) + 0.5) / size
    rows = (np.arange(size) + 0.5) / size
    glass = ((rows >= v0) & (rows < v1))[:, None] & ((cols >= u0) & (cols < u1))[None, :]
    assert np.array_equal(image[..., 3] == 0, glass)
    assert u0 >= 0.15 and 1 - u1 >= 0.15
    assert u0 == pytest.approx(1 - u1)


def test_facade_is_deterministic():
    a, rect_a = facade_texture(seed=5)
    b, rect_b = _facade.__wrapped__(128, 5, "brick")  # computed afresh, not from the cache
    assert np.array_equal(a, b) and rect_a == rect_b
    assert not np.array_equal(a, facade_texture(seed=7)[0])


# --------------------------------------------------------------------------- sky


def test_cube_directions_follow_gl_orientation():
    dirs = cube_directions(2)
    axes = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    for face, axis in enumerate(axes):
        assert np.allclose(np.sign(dirs[face].mean(axis=(0, 1))), axis)
    # GL table 8.19: on +X, s grows toward -z and t grows toward -y.
    assert dirs[0, 0, 1, 2] < dirs[0, 0, 0, 2] and dirs[0, 1, 0, 1] < dirs[0, 0, 0, 1]
    # On +Y, s grows toward +x and t toward +z.
    assert dirs[2, 0, 1, 0] > dirs[2, 0, 0, 0] and dirs[2, 1, 0, 2] > dirs[2, 0, 0, 2]


@pytest.mark.parametrize("sun", SUNS)
def test_brightest_cubemap_texel_is_toward_the_sun(sun):
    size = 64
    cube = environment_cubemap(size=size, sun_direction=sun, dusk=0.7)
    assert cube.shape == (6, size, size, 3) and cube.dtype == np.float32
    brightest = np.unravel_index(np.argmax(luminance(cube)), cube.shape[:3])
    direction = cube_directions(size)[brightest]
    sun = np.asarray(sun) / np.linalg.norm(sun)
    angle = np.arccos(np.clip(direction @ sun / np.linalg.norm(direction), -1, 1))
    texel_angle = np.pi / 2 / size
    assert angle < 1.5 * texel_angle
    assert cube.max() > 10


def test_cubemap_is_sky_colour_on_the_cube():
    cube = environment_cubemap(size=16, dusk=0.4)
    assert np.allclose(cube, sky_colour(cube_directions(16), dusk=0.4))


def test_dusk_darkens_the_zenith_and_reddens_the_horizon():
    sun = np.array([0.0, 0.15, -1.0])
    up, toward_sun = np.array([0.0, 1.0, 0.0]), np.array([0.2, 0.25, -1.0])
    day, dusk = sky_colour(up, sun, 0.0), sky_colour(up, sun, 1.0)
    assert luminance(dusk) < 0.3 * luminance(day)
    glow = sky_colour(toward_sun, sun, 1.0)
    assert glow[0] > 2 * glow[2]
    assert luminance(sky_colour(np.array([0.0, -1.0, 0.0]), sun, 0.7)) < 0.05


# --------------------------------------------------------------------------- sprites and curtain


def test_sprites_are_hard_alpha_standing_on_the_floor_and_animated():
    sprites = furniture_sprites(size=64, kinds=len(SPRITE_KINDS), frames=4, seed=2)
    assert sprites.shape == (len(SPRITE_KINDS), 4, 64, 64, 4) and sprites.dtype == np.uint8
    alpha = sprites[..., 3]
    assert set(np.unique(alpha)) == {0, 255}
    for k in range(len(SPRITE_KINDS)):
        assert (alpha[k, :, :3] == 255).any(axis=(1, 2)).all(), f"kind {k} does not reach the floor"
        assert (alpha[k, :, -4:] == 0).all(), f"kind {k} touches the ceiling"
        for frame in range(1, 4):
            changed = np.abs(sprites[k, frame].astype(int) - sprites[k, 0]).max(axis=-1) > 30
            assert changed.sum() > 20, (k, frame)
    assert np.array_equal(sprites, furniture_sprites(size=64, kinds=len(SPRITE_KINDS), frames=4, seed=2))


def test_curtain_has_vertical_folds_and_tiles():
    curtain = curtain_texture(size=64)
    assert curtain.shape == (64, 64, 4) and (curtain[..., 3] == 255).all()
    lum = luminance(curtain[..., :3].astype(float))
    assert lum[32].std() > 3 * lum[16:, 10].std()
    assert abs(lum[:, 0].mean() - lum[:, -1].mean()) < 0.1 * lum.mean()


# --------------------------------------------------------------------------- pictures


def test_write_pngs_for_inspection(output_dir):
    folder, written = output_dir / "assets", []
    rooms = room_textures()
    for face in FACES:
        written.append(save(folder, f"rooms_{face}", np.concatenate(list(rooms[face]), axis=1)))
    atlas, _ = room_atlas(rooms)
    written.append(save(folder, "room_atlas", atlas))
    written.append(
        save(
            folder, "facades", np.concatenate([np.tile(facade_texture(seed=s)[0], (2, 3, 1)) for s in range(2)], axis=1)
        )
    )
    sprites = furniture_sprites(kinds=len(SPRITE_KINDS))
    backdrop = np.array([60, 70, 80, 255], np.uint8)
    rows = [np.where(s[..., 3:] > 0, s, backdrop) for s in sprites]
    written.append(
        save(folder, "sprites", np.concatenate([np.concatenate(list(r), axis=1) for r in rows[::-1]], axis=0))
    )
    written.append(save(folder, "curtain", np.tile(curtain_texture(), (1, 3, 1))))
    cube = environment_cubemap()
    # Cube faces as uploaded: row 0 (t = 0) is the top of the face as seen from inside.
    written.append(save(folder, "cubemap_faces", tonemap(np.concatenate(list(cube[:, ::-1]), axis=1))))
    azimuth, elevation = np.meshgrid(np.linspace(-np.pi, np.pi, 512), np.linspace(-0.3, np.pi / 2, 160))
    pano = np.stack([np.cos(elevation) * np.cos(azimuth), np.sin(elevation), np.cos(elevation) * np.sin(azimuth)], -1)
    for dusk in (0.0, 0.7, 1.0):
        written.append(save(folder, f"sky_dusk{dusk:.1f}", tonemap(sky_colour(pano, dusk=dusk))))
    assert len(written) >= 12 and all(path.stat().st_size > 0 for path in written)


def test_sky_above_the_horizon_has_no_skyline():
    """Only sky above the horizon: no silhouette of buildings the data does not contain."""
    azimuth = np.linspace(-np.pi, np.pi, 2048, endpoint=False)
    for elevation in (0.005, 0.02, 0.05, 0.1):
        ring = np.stack(
            [
                np.cos(elevation) * np.cos(azimuth),
                np.full_like(azimuth, np.sin(elevation)),
                np.cos(elevation) * np.sin(azimuth),
            ],
            -1,
        )
        lum = luminance(sky_colour(ring, sun_direction=(0.0, 0.8, -0.6), dusk=0.0))
        assert lum.min() > 0.6 * lum.max(), (elevation, lum.min(), lum.max())
