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
The other views (each shadow cascade, the id AOV) are culled against their frustum only. The tree
instances go through the same tests (`run_cull` with shaders/trees/cull.glsl, from render/_trees.py).

`visible_twin` makes the same decision in numpy from the same planes and the pyramid read back.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import R32F, bind_textures, binding, create_buffer, programs, pyramid_levels, pyramid_texture, set_uniforms
from ._culling import frustum_planes

OCCLUDER_SIZE = 0.1  # half diagonal / distance: about 11 degrees across
DEPTH_MARGIN = 4e-6  # depth units (about 70 steps of a 24-bit depth buffer) a box must lie beyond the pyramid
GROUP = 64  # cull.glsl's local size
TILE = 8  # hiz.glsl's local size (each way)
# cull.glsl's BuildingBox; draw: vertex count, first vertex, building index
BOX_DTYPE = np.dtype([("lo", "f4", 4), ("hi", "f4", 4), ("draw", "u4", 4)])
COMMAND_WORDS = 5  # count, instanceCount, first, baseInstance; moderngl draws with a 20-byte stride


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


def box_pixels(view_projection: np.ndarray, lo: np.ndarray, hi: np.ndarray, viewport: tuple[int, int]):
    """Per box: whether every corner is in front of the eye, the clamped pixel range (first, last:
    (N, 2) ints) its projection can touch, and its nearest depth in [0, 1] (float32, as on the GPU)."""
    corners = np.stack([np.where(np.array([(i >> a) & 1 for a in range(3)], bool), hi, lo) for i in range(8)], 1)
    homogeneous = np.concatenate([corners, np.ones((*corners.shape[:2], 1))], axis=-1).astype(np.float32)
    clip = homogeneous @ view_projection.astype(np.float32).T  # (N, 8, 4)
    in_front = np.all(clip[..., 3] > 0, axis=1)
    safe_w = np.where(clip[..., 3] > 0, clip[..., 3], np.float32(1))
    ndc = clip[..., :3] / safe_w[..., None]
    size = np.array(viewport, np.float32)
    window = (ndc[..., :2] * np.float32(0.5) + np.float32(0.5)) * size
    top = np.array(viewport) - 1
    first = np.clip(np.floor(window.min(axis=1)).astype(np.int64), 0, top)
    last = np.clip(np.floor(window.max(axis=1)).astype(np.int64), 0, top)
    nearest = np.minimum((ndc[..., 2] * np.float32(0.5) + np.float32(0.5)).min(axis=1), np.float32(1))
    return in_front, first, last, nearest


def hiz_twin(depth: np.ndarray) -> list[np.ndarray]:
    """frame/hiz.glsl in numpy: the max-depth pyramid of a depth image (H, W[, samples]; row 0 the
    bottom row, as GL stores it), level 0 first."""
    level = depth.max(axis=2) if depth.ndim == 3 else depth
    levels = [level.astype(np.float32)]
    for w, h in pyramid_levels((depth.shape[1], depth.shape[0]))[1:]:
        finer = levels[-1]
        out = np.zeros((h, w), np.float32)
        for y in range(h):
            ys = slice(2 * y, finer.shape[0] if y == h - 1 else 2 * y + 2)
            for x in range(w):
                out[y, x] = finer[ys, 2 * x : finer.shape[1] if x == w - 1 else 2 * x + 2].max()
        levels.append(out)
    return levels


def visible_twin(
    boxes: np.ndarray,
    view_projection: np.ndarray,
    eye=None,
    pyramid: list[np.ndarray] | None = None,
    viewport: tuple[int, int] | None = None,
) -> np.ndarray:
    """frame/cull.glsl (and trees/cull.glsl) in numpy: which boxes are drawn. Frustum only; with
    `eye`, the occluders; with `pyramid` (hiz_twin's or the GPU's levels) and `viewport`, the Hi-Z
    test too."""
    planes = frustum_planes(view_projection).astype(np.float32)
    lo, hi = boxes["lo"][:, :3], boxes["hi"][:, :3]
    corner = np.where(planes[None, :, :3] >= 0, hi[:, None, :], lo[:, None, :])
    drawn = np.all(np.sum(corner * planes[None, :, :3], axis=-1) + planes[None, :, 3] >= 0, axis=1)
    if eye is not None:
        centre = np.float32(0.5) * (lo + hi)
        half = np.float32(0.5) * np.linalg.norm(hi - lo, axis=1)
        distance = np.linalg.norm(centre - np.asarray(eye, np.float32), axis=1)
        return drawn & (half >= np.float32(OCCLUDER_SIZE) * distance)
    if pyramid is not None:
        in_front, first, last, nearest = box_pixels(view_projection, lo, hi, viewport)
        farthest = np.zeros(len(boxes), np.float32)
        for i in np.flatnonzero(drawn & in_front):
            a, b, level = first[i], last[i], 0
            while level < len(pyramid) - 1 and np.any(b - a > 1):
                level += 1
                top = np.array(pyramid[level].shape[::-1]) - 1
                a, b = np.minimum(first[i] >> level, top), np.minimum(last[i] >> level, top)
            farthest[i] = pyramid[level][a[1] : b[1] + 1, a[0] : b[0] + 1].max()
        drawn &= ~(in_front & (nearest > farthest + np.float32(DEPTH_MARGIN)))
    return drawn


def run_cull(
    ctx: moderngl.Context,
    path: str,
    count: int,
    out: moderngl.Buffer,
    view_projection: np.ndarray,
    pyramid: moderngl.Texture | None = None,
    defines: dict | None = None,
    **uniforms,
):
    """Runs a cull compute shader (`path`, one invocation per box; its inputs bound by the caller)
    that writes draw commands into `out`: frustum test, and with `pyramid` (a max-depth pyramid of
    the view's depth, as large as its viewport) the Hi-Z test."""
    defines = {"COMMAND_WORDS": COMMAND_WORDS, "HIZ": pyramid is not None, **(defines or {})}
    program = programs(ctx).get(path, defines)
    program["u_planes"].write(frustum_planes(view_projection).astype(np.float32).tobytes())
    if pyramid is not None:
        bind_textures(program, {"u_hiz": pyramid})
        uniforms.update(
            u_cull_view_proj=view_projection,
            u_viewport=pyramid.size,
            u_hiz_top=len(pyramid_levels(pyramid.size)) - 1,
            u_depth_margin=DEPTH_MARGIN,
        )
    set_uniforms(program, **uniforms)
    out.bind_to_storage_buffer(binding("Commands"))
    program.run(-(-count // GROUP))
    ctx.memory_barrier()  # the commands feed indirect draws and read-backs


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


# -- the frame's passes (render/_frame.py): `f` is the frame's FrameInputs ------------------------------


def occluder_pass(f):
    """The big buildings in the frustum, depth-only, into the frame's depth buffer."""
    draws = f.gpu.city.visibility.occluders(f.view.view_projection)
    for program in f.buildings_depth_programs():  # as the prepass: no deeper than the relief may reach
        f.gpu.city.draw_buildings(program, draws=draws)


def hiz_pass(f):
    f.gpu.city.visibility.build_pyramid(f.gpu.targets.hdr.depth, f.gpu.targets.hdr.samples)


def farthest_pass(f):
    f.gpu.city.visibility.build_farthest(f.gpu.targets.hdr.depth, f.gpu.targets.hdr.samples)


def cull_pass(f):
    f.gpu.camera_draws = f.gpu.city.visibility.cull(f.view.view_projection)
