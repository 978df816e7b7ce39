"""The polygonised-interiors baseline on the GPU (interior-mapping §3.1): one vertex buffer per
layer (floors, ceilings, walls) for the whole city, culled by the same frustum chunks as the
interior-mapped buildings, one draw call per layer; and its passes of the frame, the rooms between
the exterior walls and the window glass the buildings' program draws."""

from __future__ import annotations

import moderngl
import numpy as np

from ..frame import HDR, BuildingChunks, Frame, GLState, Pass, chunk_vertices
from ..gl import VertexArrays, bind_textures, binding, create_buffer, set_uniforms
from ..scene import GPU_VERTEX_ATTRIBUTES, GPU_VERTEX_FORMAT, City, face_table, placements
from ._polygonised import LAYERS as POLYGONISED_LAYERS
from ._polygonised import polygonised_vertices

ROOM_TEXTURES = ("room textures", "facade texture", "sprites", "curtain", "environment")


class PolygonisedGPU:
    def __init__(self, ctx: moderngl.Context, city: City):
        self.ctx = ctx
        self.layers: dict[str, tuple[BuildingChunks, moderngl.Buffer, moderngl.Buffer]] = {}  # chunks, vertices, faces
        self.triangle_count = 0
        placement = placements(city.masses)
        self.placements = create_buffer(ctx, placement)  # the vertex stage places the rooms as the buildings
        for name, vertices in polygonised_vertices(city.masses).items():
            if len(vertices):
                vertices, chunks = chunk_vertices(vertices)
                vertices, faces = face_table(vertices, placement)
                self.layers[name] = (chunks, create_buffer(ctx, vertices), create_buffer(ctx, faces))
                self.triangle_count += len(vertices) // 3
        self._vaos = VertexArrays(ctx)

    def draw(self, program: moderngl.Program, layer: str, view_projection: np.ndarray):
        if layer not in self.layers:
            return
        chunks, vbo, faces = self.layers[layer]
        faces.bind_to_storage_buffer(binding("BuildingFaces"))
        self.placements.bind_to_storage_buffer(binding("BuildingPlacements"))
        vao = self._vaos.get((program.glo, layer), program, [(vbo, GPU_VERTEX_FORMAT, *GPU_VERTEX_ATTRIBUTES)])
        for first, count in chunks.visible_runs(chunks.visible(view_projection)):
            vao.render(moderngl.TRIANGLES, vertices=count, first=first)

    def release(self):
        self._vaos.release()
        self.placements.release()
        for _, vbo, faces in self.layers.values():
            vbo.release()
            faces.release()


def draw_interior_depth(f: Frame):
    """The rooms' depth only (the baseline's own prepass): floors, ceilings and walls."""
    program = f.programs.get("interior/polygonised.glsl", {"DEPTH_ONLY": True})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    for layer in POLYGONISED_LAYERS:
        f.city.polygonised().draw(program, layer, f.view.view_projection)


def draw_interior_layers(f: Frame):
    """Floors, ceilings, then walls: three draw calls, each layer its own texture kind (the frame's
    pass culls back faces: a floor and the ceiling below it share a plane)."""
    program = f.programs.get("interior/polygonised.glsl", {"IM_SINGLE_ATLAS": f.view.settings.single_atlas})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    bind_textures(program, f.room_textures)
    f.city.records.bind_to_storage_buffer(binding("Buildings"))
    for layer in POLYGONISED_LAYERS:
        f.city.polygonised().draw(program, layer, f.view.view_projection)


def room_passes(depth_prepass: bool) -> list[Pass]:
    """Real floors, ceilings and walls behind the exterior walls (a floor and the ceiling below it
    share a plane: back faces culled); with `depth_prepass` their own z-cull first, so each visible
    room pixel is shaded once."""
    passes = []
    room_depth = "<"
    if depth_prepass:
        passes.append(
            Pass(
                "room depth prepass",
                draw_interior_depth,
                ("room geometry",),
                HDR,
                GLState(colour_write=False, cull=True),
            )
        )
        room_depth = "<="
    passes.append(
        Pass(
            "rooms",
            draw_interior_layers,
            ("room geometry", *ROOM_TEXTURES),
            HDR,
            GLState(depth_func=room_depth, cull=True),
        )
    )
    return passes
