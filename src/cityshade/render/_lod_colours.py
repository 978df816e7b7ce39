"""The cheap level's colours on the GPU (shaders/grammar/lod_colours.glsl): each grammar
building's sample face evaluated by the frame's own grammar program at the numpy reference's
points (render/_building_lod.py: grammar_colours is the twin), a tile of pixels per building, a
batch of buildings per draw, the tiles' means taken from the read-back batch. About a
millisecond per building here, where the numpy reference takes fourteen."""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import RenderTarget, bind_textures, create_buffer, draw_fullscreen, programs, set_uniforms, upload_texture
from ..grammar import GrammarTextures, seed_vector, shader_defines
from ._building_lod import SAMPLE_GRID, unit_samples

TILES = (32, 32)  # buildings per batch: tiles across and up (a 1024 x 512 target)


def _face_rows(faces: np.ndarray) -> np.ndarray:
    """The shader's SampleFace per row of grammar_sample_faces (3 vec4)."""
    rows = np.zeros((len(faces), 12), np.float32)
    rows[:, 0], rows[:, 1] = faces["width"], faces["height"]
    rows[:, 2], rows[:, 3] = faces["start"], faces["face"]
    rows[:, 4], rows[:, 5] = faces["storeys"], faces["style"]
    rows[:, 6], rows[:, 7] = faces["use"], faces["mass_height"]
    rows[:, 8:10] = [seed_vector(int(seed)) for seed in faces["seed"]]
    rows[:, 10] = faces["level"]
    return rows


def grammar_colours_gpu(ctx: moderngl.Context, grammar: GrammarTextures, faces: np.ndarray, count: int) -> np.ndarray:
    """(count, 4) float32 as render/_building_lod.py's grammar_colours, evaluated on the GPU:
    per building its grammar's mean wall colour (linear) and glass share; zero where no grammar."""
    colours = np.zeros((count, 4), np.float32)
    if not len(faces):
        return colours
    cols, rows = SAMPLE_GRID
    program = programs(ctx).get(
        "grammar/lod_colours.glsl", {**shader_defines(), "LOD_SAMPLES_X": cols, "LOD_SAMPLES_Y": rows}
    )
    unit = upload_texture(ctx, unit_samples().astype(np.float32).reshape(rows, cols, 2), "stored", mipmaps=False)
    params = create_buffer(ctx, _face_rows(faces))
    target = RenderTarget(ctx, (cols * TILES[0], rows * TILES[1]), colors=(("f4", 4),))
    per_batch = TILES[0] * TILES[1]
    try:
        target.use()
        ctx.viewport = (0, 0, *target.size)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        grammar.bind(program)
        bind_textures(program, {"u_unit_samples": unit})
        params.bind_to_storage_buffer(0)
        for first in range(0, len(faces), per_batch):
            set_uniforms(program, u_first=first, u_tiles_across=TILES[0], u_face_count=len(faces))
            draw_fullscreen(program)
            pixels = target.read()[::-1].astype(np.float64)  # bottom row first, as the shader's tiles
            tiles = pixels.reshape(TILES[1], rows, TILES[0], cols, 4).mean(axis=(1, 3)).reshape(-1, 4)
            tiles = tiles[: min(per_batch, len(faces) - first)]
            wall = tiles[:, 3]
            colours[faces["building"][first : first + len(tiles)]] = np.column_stack(
                [tiles[:, :3] / np.maximum(wall, 1e-6)[:, None], 1.0 - wall]
            )
    finally:
        for owned in (unit, params, target):
            owned.release()
    return colours
