"""A city uploaded to the GPU: one vertex and index buffer for all buildings (ordered chunk by
chunk, each building a contiguous range) with their face table and placements
(scene/_face_table.py), one SSBO of building records, the buildings' boxes for the cull pass, and
the ground quads. Vertex arrays are cached per program. No CPU copy of the vertices or records
stays once they are uploaded (a city of 100,000 buildings meshes 250 MB of vertices)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import moderngl
import numpy as np

from ..frame import BuildingChunks, chunk_vertices
from ..gl import VertexArrays, binding, create_buffer
from ..grammar import FACADE_GRAMMAR, GrammarTextures
from ..interior import PolygonisedGPU
from ..relief import CityRelief
from ..scene import (
    BUILDING_DTYPE,
    GPU_VERTEX_ATTRIBUTES,
    GPU_VERTEX_FORMAT,
    GROUND_ASPHALT,
    GROUND_GRASS,
    City,
    batch,
    face_table,
    placements,
    shared_vertices,
)
from ._building_lod import grammar_sample_faces
from ._facades import assign_facades
from ._lod_colours import LodColours
from ._street_lights import StreetLightsGPU
from ._visibility import BuildingVisibility, building_bounds, building_boxes, building_ranges

GROUND_FORMAT = "3f 1f"
GROUND_ATTRIBUTES = ("in_position", "in_material")
GROUND_MARGIN = 400.0


def ground_vertices(city: City) -> np.ndarray:
    """Two triangles per ground rectangle, drawn in order (later ones on top, lifted slightly);
    a city from a map brings its own triangles."""
    if city.ground_mesh is not None:
        return np.ascontiguousarray(city.ground_mesh, dtype=np.float32)
    x0, z0, x1, z1 = city.bounds
    rects = [(x0 - GROUND_MARGIN, z0 - GROUND_MARGIN, x1 + GROUND_MARGIN, z1 + GROUND_MARGIN, GROUND_ASPHALT)]
    rects += list(city.ground)
    out = []
    for layer, (a, b, c, d, material) in enumerate(rects):
        y = 0.02 * min(layer, 1) + 0.01 * (material == GROUND_GRASS)  # pavements and parks sit on the asphalt
        corners = [(a, y, b), (a, y, d), (c, y, d), (c, y, b)]
        for i in (0, 1, 2, 0, 2, 3):
            out.append((*corners[i], float(material)))
    return np.asarray(out, dtype=np.float32)


def _at_least_one(rows: np.ndarray) -> np.ndarray:
    """A storage buffer's rows, a zero one if there are none (a buffer may not be empty)."""
    return rows if len(rows) else np.zeros(1, rows.dtype)


@dataclass
class CityBuildings:
    """The buildings as the GPU gets them: vertices in chunk order (each building a contiguous
    range), records with their facades assigned, the cull pass's boxes, and what the cheap far
    colours and the statistics need. Made once per city; a tile cache (render/_tile_cache.py)
    stores them cut into tiles."""

    vertices: np.ndarray
    records: np.ndarray
    chunks: BuildingChunks
    facades: Counter
    lod_faces: np.ndarray  # SAMPLE_FACE_DTYPE, by building

    @classmethod
    def of(cls, masses: list) -> CityBuildings:
        vertices, records = batch(masses)
        facades = assign_facades(records, masses, vertices)  # buildings per facade kind (narrow faces: plain)
        lod_faces = grammar_sample_faces(masses, records, vertices)
        vertices, chunks = chunk_vertices(vertices)
        return cls(vertices, records, chunks, facades, lod_faces)

    def boxes(self) -> np.ndarray:
        return building_boxes(self.vertices, *building_ranges(self.vertices, len(self.records)))


class CityGPU:
    def __init__(self, ctx: moderngl.Context, city: City):
        self._upload_city(ctx, city)
        buildings = CityBuildings.of(list(city.masses))  # mass objects for the meshing only: the city keeps columns
        self.facades = buildings.facades
        self._lod_faces = buildings.lod_faces
        self.chunks = buildings.chunks
        self.building_vertex_count = len(buildings.vertices)
        self.visibility = BuildingVisibility(ctx, buildings.boxes())
        vertices, faces = face_table(buildings.vertices, placements(city.masses))
        vertices, indices = shared_vertices(vertices)
        self.building_vbo = create_buffer(ctx, vertices) if len(vertices) else None
        self.building_indices = create_buffer(ctx, indices) if len(indices) else None
        self._upload_records(buildings.records)
        self._upload_faces(faces)

    def _upload_city(self, ctx: moderngl.Context, city: City):
        """Everything but the building vertices: ground, street lights, relief maps."""
        self.ctx = ctx
        self.city = city
        self.building_count = len(city.masses)
        self._lod_colours: LodColours | None = None
        self.relief = CityRelief(ctx)
        ground = ground_vertices(city)
        self.ground_vbo = create_buffer(ctx, ground)
        self.ground_vertex_count = len(ground)
        self.placements = create_buffer(ctx, _at_least_one(placements(city.masses)))  # yaws and origins
        self.street_lights = StreetLightsGPU(ctx, city.lights)
        self._vaos = VertexArrays(ctx)
        self._polygonised: PolygonisedGPU | None = None

    def _upload_faces(self, faces: np.ndarray):
        self.faces = create_buffer(self.ctx, _at_least_one(faces))

    def _bind_vertex_tables(self):
        """The storage buffers the buildings' vertex stage reads (common/building_vertex.glsl)."""
        self.faces.bind_to_storage_buffer(binding("BuildingFaces"))
        self.placements.bind_to_storage_buffer(binding("BuildingPlacements"))
        self.visibility.bounds.bind_to_storage_buffer(binding("BuildingBounds"))

    def _upload_records(self, records: np.ndarray):
        self.records = create_buffer(self.ctx, records)
        self._assigned_starts = records["facade"][:, 1].copy()  # the one word start_grammars_at changes

    def _vao(self, program, vbo, fmt, attributes, index_buffer=None):
        return self._vaos.get((id(program), id(vbo)), program, [(vbo, fmt, *attributes)], index_buffer)

    def draw_buildings(self, program, view_projection: np.ndarray | None = None, draws: moderngl.Buffer | None = None):
        """All buildings in one call; with `draws` (commands of BuildingVisibility), one multi-draw
        indirect call of a command per building, in the same order; with a view-projection, only
        the chunks inside its frustum (one call per run of neighbouring visible chunks). Ranges and
        commands count the vertices of the meshed triangle list: with the index buffer, its indices."""
        if self.building_vbo is None:
            return
        self.records.bind_to_storage_buffer(binding("Buildings"))
        self._bind_vertex_tables()
        vao = self._vao(program, self.building_vbo, GPU_VERTEX_FORMAT, GPU_VERTEX_ATTRIBUTES, self.building_indices)
        if draws is not None:
            vao.render_indirect(draws, moderngl.TRIANGLES, count=self.visibility.count)
        elif view_projection is not None:
            for first, count in self.chunks.visible_runs(self.chunks.visible(view_projection)):
                vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        else:
            vao.render(moderngl.TRIANGLES)

    def start_grammars_at(self, address: int | None):
        """Every grammar facade starts at rule `address` of the grammar texture (RenderSettings.grammar_start);
        None: each building's own style, as assigned."""
        if not len(self._assigned_starts):  # a city without buildings (its buffer holds a placeholder)
            return
        records = np.frombuffer(self.records.read(), BUILDING_DTYPE).copy()
        records["facade"][:, 1] = self._assigned_starts
        if address is not None:
            records["facade"][records["facade"][:, 0] == FACADE_GRAMMAR, 1] = address
        self.records.write(records.tobytes())

    def lod_colours(self) -> LodColours:
        """The grammar buildings' cheap colours (city/lod.glsl), none evaluated until a view needs them."""
        if self._lod_colours is None:
            bounds = building_bounds(self.visibility.boxes) if len(self._lod_faces) else np.zeros((0, 2, 4), np.float32)
            self._lod_colours = LodColours(self.ctx, self._lod_faces, bounds, self.building_count)
        return self._lod_colours

    def drawn_buildings(self) -> np.ndarray | None:
        """Per building, whether it can be drawn now (None: all of them)."""
        return None

    def update_lod_colours(self, grammar: GrammarTextures, camera, size, distances, budget: int | None) -> int:
        """Evaluates the cheap colours the view of `camera` (a viewport `size`, the ShadingBlock's
        lod_distances) needs, at most `budget` of them (None: all), nearest first; returns how many.
        Before a frame's passes, since it draws into a target of its own."""
        colours = self.lod_colours()
        needed = colours.needed(
            camera.view_projection(size[0] / size[1]), camera.eye, distances[2], self.drawn_buildings()
        )
        colours.evaluate(grammar, needed[:budget])
        return colours.last_count

    def bind_lod_colours(self):
        """Binds the cheap colours (a building not evaluated yet reads as not ready)."""
        self.lod_colours().bind()

    def polygonised(self) -> PolygonisedGPU:
        """Real interior geometry for the polygonised-interiors baseline, built on first use."""
        if self._polygonised is None:
            self._polygonised = PolygonisedGPU(self.ctx, self.city)
        return self._polygonised

    def draw_ground(self, program):
        self._vao(program, self.ground_vbo, GROUND_FORMAT, GROUND_ATTRIBUTES).render(moderngl.TRIANGLES)

    def release(self):
        self._vaos.release()
        for buf in (
            self.building_vbo,
            self.building_indices,
            self.faces,
            self.placements,
            self.records,
            self.ground_vbo,
            self._lod_colours,
        ):
            if buf is not None:
                buf.release()
        self.relief.release()
        self.visibility.release()
        self.street_lights.release()
        if self._polygonised is not None:
            self._polygonised.release()
