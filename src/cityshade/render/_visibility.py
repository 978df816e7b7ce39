"""GPU-driven visibility of the city's buildings (shaders/frame/cull.glsl, frame/hiz.glsl).

Each building is one contiguous range of the city's triangle list (indices of its index buffer, or
vertices of a streamed city's arena) with a bounding box; a compute pass writes one indirect draw
command per building (count, instanceCount (0 when culled), first index or vertex, 0: read as a
DrawElementsIndirectCommand with base vertex 0, or a DrawArraysIndirectCommand) and the buildings are drawn with one multi-draw indirect call, in vertex-buffer order, so the picture
is that of drawing everything. Per building rather than per chunk: a building's box is tight, so
it hides behind the street's first row where a chunk's box (a whole block, its tallest tower
included) would not.

For the camera the frame culls in three steps, all within the frame (no depth from an earlier
frame, so the first frame and camera cuts are as exact as any other):
1. `occluders`: the buildings in the frustum that look big (half their box's diagonal at least
   OCCLUDER_SIZE of their distance) are drawn depth-only into the frame's depth buffer;
2. `hi-z`: that depth is reduced to a max-depth pyramid (the farthest of each pixel's samples);
3. `cull`: every building is tested against the frustum and the pyramid; a box hidden in every
   pixel it could cover is dropped (an occluder too, when a nearer one hides it all).
The other views (each shadow cascade, the id AOV) are culled against their frustum only. The tests
themselves, and their numpy twin, are the frame's (frame/_gpu_culling.py): the tree instances go
through them too.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..frame import BOX_DTYPE, COMMAND_WORDS, HDR, OCCLUDER_SIZE, Frame, run_cull
from ..gl import R32F, bind_textures, binding, create_buffer, programs, pyramid_levels, pyramid_texture, set_uniforms
from ._buildings import buildings_depth_programs

TILE = 8  # hiz.glsl's local size (each way)


def building_ranges(vertices: np.ndarray, building_count: int) -> tuple[np.ndarray, np.ndarray]:
    """(first vertex, vertex count) of each building, whose vertices must be contiguous."""
    building = vertices["ids"][:, 0]
    count = np.bincount(building, minlength=building_count)
    first = np.zeros(building_count, dtype=np.int64)
    starts = np.flatnonzero(np.r_[True, building[1:] != building[:-1]])[: len(building)]  # none without vertices
    first[building[starts]] = starts
    if len(starts) != np.count_nonzero(count):
        raise ValueError("a building's vertices are not contiguous in the vertex buffer")
    return first, count


def building_boxes(vertices: np.ndarray, first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """The cull pass's input: the box, vertex range and index of each building with vertices, in
    vertex-buffer order, which the draw commands keep (where two buildings' surfaces meet at one
    depth, the one drawn later wins, as in one plain draw)."""
    buildings = np.flatnonzero(count > 0)
    buildings = buildings[np.argsort(first[buildings], kind="stable")]
    boxes = np.zeros(len(buildings), BOX_DTYPE)
    if len(buildings):
        positions = vertices["position"].astype(np.float32)
        boxes["lo"][:, :3] = np.minimum.reduceat(positions, first[buildings], axis=0)
        boxes["hi"][:, :3] = np.maximum.reduceat(positions, first[buildings], axis=0)
    boxes["draw"][:, 0], boxes["draw"][:, 1], boxes["draw"][:, 2] = count[buildings], first[buildings], buildings
    return boxes


def building_bounds(boxes: np.ndarray) -> np.ndarray:
    """The boxes by building index, (buildings, 2, 4) float32: low and high corner (zero for a
    building without vertices), for the buildings' vertex stage."""
    buildings = boxes["draw"][:, 2]
    bounds = np.zeros((int(buildings.max()) + 1 if len(boxes) else 0, 2, 4), np.float32)
    bounds[buildings, 0], bounds[buildings, 1] = boxes["lo"], boxes["hi"]
    return bounds


class BuildingVisibility:
    """The cull pass's buffers and programs for one uploaded city."""

    def __init__(self, ctx: moderngl.Context, boxes: np.ndarray):
        self.ctx = ctx
        self.count = len(boxes)  # the boxes live on the GPU only: no CPU copy for a city's life
        # per box: vertex count, first vertex, building (the draws change as tiles stream; the boxes don't)
        self.draw_buffer = create_buffer(ctx, np.ascontiguousarray(boxes["draw"]))
        self.bounds = create_buffer(ctx, building_bounds(boxes))  # per building: its box's corners, once
        size = max(self.count, 1) * COMMAND_WORDS * 4
        self.frustum_draws = create_buffer(ctx, reserve=size)  # any view, frustum only (reused per call)
        self.occluder_draws = create_buffer(ctx, reserve=size)
        self.camera_draws = create_buffer(ctx, reserve=size)  # frustum and Hi-Z
        self.pyramid: moderngl.Texture | None = None
        self.farthest: moderngl.Texture | None = None  # after the depth prepass (build_farthest)

    @property
    def boxes(self) -> np.ndarray:
        """The boxes as uploaded (read back from the GPU): each draw with its building's corners."""
        boxes = np.zeros(self.count, BOX_DTYPE)
        boxes["draw"] = np.frombuffer(self.draw_buffer.read(), np.uint32, count=4 * self.count).reshape(-1, 4)
        corners = np.frombuffer(self.bounds.read(), np.float32).reshape(-1, 2, 4)[boxes["draw"][:, 2]]
        boxes["lo"], boxes["hi"] = corners[:, 0], corners[:, 1]
        return boxes

    def upload_draws(self, boxes: np.ndarray):
        """New draw fields for the boxes (a streamed city's, as its tiles come and go)."""
        self.draw_buffer.write(np.ascontiguousarray(boxes["draw"]).tobytes())

    def _run(
        self,
        out: moderngl.Buffer,
        view_projection: np.ndarray,
        defines: dict | None = None,
        pyramid: moderngl.Texture | None = None,
        **uniforms,
    ) -> moderngl.Buffer:
        self.draw_buffer.bind_to_storage_buffer(binding("Draws"))
        self.bounds.bind_to_storage_buffer(binding("BuildingBounds"))
        run_cull(
            self.ctx,
            "frame/cull.glsl",
            self.count,
            out,
            view_projection,
            pyramid,
            defines,
            u_box_count=self.count,
            **uniforms,
        )
        return out

    def frustum(self, view_projection: np.ndarray) -> moderngl.Buffer:
        """Draw commands of the buildings inside the frustum of `view_projection`."""
        return self._run(self.frustum_draws, view_projection)

    def occluders(self, view_projection: np.ndarray) -> moderngl.Buffer:
        """Draw commands of the big buildings in the camera's frustum (the eye is FrameBlock's u_camera)."""
        return self._run(self.occluder_draws, view_projection, {"OCCLUDERS": True}, u_occluder_size=OCCLUDER_SIZE)

    def _farthest_samples(self, depth: moderngl.Texture, samples: int, out: moderngl.Texture):
        """Level 0 of `out`: the farthest of each pixel's samples of `depth` (frame/hiz.glsl FROM_DEPTH)."""
        program = programs(self.ctx).get("frame/hiz.glsl", {"FROM_DEPTH": True, "MULTISAMPLED": samples > 0})
        bind_textures(program, {"u_depth": depth})
        set_uniforms(program, **({"u_samples": samples} if samples else {}))
        out.bind_to_image(binding("u_level"), read=False, write=True, level=0, format=R32F)
        w, h = depth.size
        program.run(-(-w // TILE), -(-h // TILE))
        self.ctx.memory_barrier()

    def _fitted(self, texture: moderngl.Texture | None, size: tuple[int, int]) -> moderngl.Texture:
        """`texture` if it has `size`, else a new pyramid texture of that size (the old one released)."""
        if texture is not None and texture.size == size:
            return texture
        if texture is not None:
            texture.release()
        return pyramid_texture(self.ctx, size)

    def build_pyramid(self, depth: moderngl.Texture, samples: int):
        """The max-depth pyramid of a depth texture (the frame's, after the occluders)."""
        size = depth.size
        self.pyramid = self._fitted(self.pyramid, size)
        self._farthest_samples(depth, samples, self.pyramid)
        reduce = programs(self.ctx).get("frame/hiz.glsl")
        for level, (w, h) in enumerate(pyramid_levels(size)[1:], start=1):
            self.pyramid.bind_to_image(binding("u_finer"), read=True, write=False, level=level - 1, format=R32F)
            self.pyramid.bind_to_image(binding("u_level"), read=False, write=True, level=level, format=R32F)
            reduce.run(-(-w // TILE), -(-h // TILE))
            self.ctx.memory_barrier()

    def build_farthest(self, depth: moderngl.Texture, samples: int):
        """The farthest of each pixel's samples of `depth` (the frame's, after the depth prepass), in a
        texture of its own (`farthest`): the buildings pass rejects a fragment beyond it before
        shading it (city/building.glsl PREPASS_FARTHEST)."""
        self.farthest = self._fitted(self.farthest, depth.size)  # only its level 0 is filled and read
        self._farthest_samples(depth, samples, self.farthest)

    def cull(self, view_projection: np.ndarray) -> moderngl.Buffer:
        """Draw commands of the buildings in the frustum and not hidden behind the pyramid."""
        return self._run(self.camera_draws, view_projection, pyramid=self.pyramid)

    def read_pyramid(self) -> list[np.ndarray]:
        """The pyramid's levels as float32 arrays (row 0 the bottom row)."""
        return [
            np.frombuffer(self.pyramid.read(level=level), np.float32).reshape(h, w)
            for level, (w, h) in enumerate(pyramid_levels(self.pyramid.size))
        ]

    def drawn(self, commands: moderngl.Buffer) -> np.ndarray:
        """Which boxes (in `boxes` order; their building is boxes["draw"][:, 2]) a command buffer
        draws (read back: for tests and statistics)."""
        return np.frombuffer(commands.read(), np.uint32).reshape(-1, COMMAND_WORDS)[: self.count, 1] > 0

    def release(self):
        for buffer in (self.draw_buffer, self.bounds, self.frustum_draws, self.occluder_draws, self.camera_draws):
            buffer.release()
        for texture in (self.pyramid, self.farthest):
            if texture is not None:
                texture.release()


# -- the frame's passes (render/_frame.py) ------------------------------------------------------------


def occluder_pass(f: Frame):
    """The big buildings in the frustum, depth-only, into the frame's depth buffer."""
    draws = f.city.visibility.occluders(f.view.view_projection)
    for program in buildings_depth_programs(f):  # as the prepass: no deeper than the relief may reach
        f.city.draw_buildings(program, draws=draws)


def hiz_pass(f: Frame):
    hdr = f.targets[HDR.name]
    f.city.visibility.build_pyramid(hdr.depth, hdr.samples)
    f.depth_pyramid = f.city.visibility.pyramid


def farthest_pass(f: Frame):
    hdr = f.targets[HDR.name]
    f.city.visibility.build_farthest(hdr.depth, hdr.samples)


def cull_pass(f: Frame):
    f.camera_draws = f.city.visibility.cull(f.view.view_projection)
