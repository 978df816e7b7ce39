"""The cheap level's colours on the GPU (shaders/grammar/lod_colours.glsl): each grammar
building's sample face evaluated by the frame's own grammar program at the numpy reference's
points (render/_building_lod.py: grammar_colours is the twin), a tile of pixels per building, a
batch of buildings per draw, the tiles' means taken from the read-back batch. From a quarter of a
millisecond per building here in full batches to one in a frame's 32, where the numpy reference
takes fourteen.

`LodColours` evaluates them lazily: a building's colour only once a view draws it (its box in the
frustum) and some of it lies beyond the cheap band's start (less a margin, so that a camera moving
on finds it ready), nearest first. Until then its glass share reads NOT_READY, and city/lod.glsl
keeps the building at the finer level: a colour never evaluated is never drawn."""

from __future__ import annotations

import moderngl
import numpy as np

from ..frame import boxes_visible, frustum_planes
from ..gl import (
    RenderTarget,
    bind_textures,
    binding,
    create_buffer,
    draw_fullscreen,
    programs,
    set_uniforms,
    upload_texture,
)
from ..grammar import GrammarTextures, seed_vector, shader_defines
from ._building_lod import SAMPLE_GRID, unit_samples

TILES = (32, 32)  # buildings per batch at most: tiles across and up (a 1024 x 512 target)
NOT_READY = -1.0  # the glass share of a colour not evaluated yet (city/lod.glsl lod_colour_ready)
APPROACH = 0.8  # colours are evaluated from this share of the cheap band's start distance on


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


def grammar_colours_gpu(ctx: moderngl.Context, grammar: GrammarTextures, faces: np.ndarray) -> np.ndarray:
    """(len(faces), 4) float32 as render/_building_lod.py's grammar_colours for these faces' buildings,
    evaluated on the GPU: per face its grammar's mean wall colour (linear) and glass share."""
    colours = np.zeros((len(faces), 4), np.float32)
    if not len(faces):
        return colours
    cols, rows = SAMPLE_GRID
    program = programs(ctx).get(
        "grammar/lod_colours.glsl", {**shader_defines(), "LOD_SAMPLES_X": cols, "LOD_SAMPLES_Y": rows}
    )
    per_batch = TILES[0] * TILES[1]
    tiles_up = min(TILES[1], -(-len(faces) // TILES[0]))  # a few buildings: a target only as tall as they need
    unit = upload_texture(ctx, unit_samples().astype(np.float32).reshape(rows, cols, 2), "stored", mipmaps=False)
    params = create_buffer(ctx, _face_rows(faces))
    target = RenderTarget(ctx, (cols * TILES[0], rows * tiles_up), colors=(("f4", 4),))
    try:
        target.use()
        ctx.viewport = (0, 0, *target.size)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        grammar.bind(program)
        bind_textures(program, {"u_unit_samples": unit})
        params.bind_to_storage_buffer(binding("SampleFaces"))
        for first in range(0, len(faces), per_batch):
            set_uniforms(program, u_first=first, u_tiles_across=TILES[0], u_face_count=len(faces))
            draw_fullscreen(program)
            pixels = target.read()[::-1].astype(np.float64)  # bottom row first, as the shader's tiles
            tiles = pixels.reshape(tiles_up, rows, TILES[0], cols, 4).mean(axis=(1, 3)).reshape(-1, 4)
            tiles = tiles[: min(per_batch, len(faces) - first)]
            wall = tiles[:, 3]
            colours[first : first + len(tiles)] = np.column_stack(
                [tiles[:, :3] / np.maximum(wall, 1e-6)[:, None], 1.0 - wall]
            )
    finally:
        for owned in (unit, params, target):
            owned.release()
    return colours


class LodColours:
    """The storage buffer of every building's cheap colour (BuildingLodColours, by building index),
    its grammar buildings' filled in as views need them. faces: grammar_sample_faces; bounds:
    visibility.building_bounds (each building's box)."""

    def __init__(self, ctx: moderngl.Context, faces: np.ndarray, bounds: np.ndarray, count: int):
        self.ctx = ctx
        self.faces = faces
        buildings = faces["building"]
        self.lo, self.hi = bounds[buildings, 0, :3], bounds[buildings, 1, :3]
        self.pending = np.ones(len(faces), bool)
        colours = np.zeros((max(count, 1), 4), np.float32)
        colours[buildings, 3] = NOT_READY
        self.buffer = create_buffer(ctx, colours)
        self.last_count = 0  # colours evaluated by the last update

    def needed(
        self, view_projection: np.ndarray, eye: np.ndarray, start: float, drawn: np.ndarray | None = None
    ) -> np.ndarray:
        """The pending faces (indices) a view needs, nearest first: the box in the frustum, its
        farthest corner beyond APPROACH x the cheap band's `start` (metres) from `eye`, and, where
        `drawn` (per building) is given, the building drawn at all."""
        pending = np.flatnonzero(self.pending)
        if drawn is not None:
            pending = pending[drawn[self.faces["building"][pending]]]
        lo, hi = self.lo[pending], self.hi[pending]
        farthest = np.linalg.norm(np.maximum(np.abs(lo - eye), np.abs(hi - eye)), axis=1)
        far = farthest >= APPROACH * start
        pending, lo, hi = pending[far], lo[far], hi[far]
        pending = pending[boxes_visible(frustum_planes(view_projection), lo, hi)]
        nearest = np.linalg.norm(np.clip(eye, self.lo[pending], self.hi[pending]) - eye, axis=1)
        return pending[np.argsort(nearest, kind="stable")]

    def evaluate(self, grammar: GrammarTextures, chosen: np.ndarray):
        """Evaluates the chosen faces' colours (indices into faces) into the buffer."""
        chosen = chosen[self.pending[chosen]]
        colours = grammar_colours_gpu(self.ctx, grammar, self.faces[chosen])
        for building, colour in zip(self.faces["building"][chosen].tolist(), colours):
            self.buffer.write(colour.tobytes(), offset=building * colour.nbytes)
        self.pending[chosen] = False
        self.last_count = len(chosen)

    def bind(self):
        self.buffer.bind_to_storage_buffer(binding("BuildingLodColours"))

    def release(self):
        self.buffer.release()
