"""GPU culling any pass can use: a compute shader tests boxes against a view's frustum and, with a
max-depth pyramid of that view's depth (frame/hiz.glsl), against what is already drawn, and writes
one indirect draw command per box (count, instanceCount (0 when culled), first, 0). The buildings'
cull passes (render/_visibility.py) and the trees' (trees/_tree_pass.py) run it.

`visible_twin` makes the same decision in numpy from the same planes and the pyramid read back.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import bind_textures, binding, programs, pyramid_levels, set_uniforms
from ._culling import frustum_planes

OCCLUDER_SIZE = 0.1  # half diagonal / distance: about 11 degrees across
DEPTH_MARGIN = 4e-6  # depth units (about 70 steps of a 24-bit depth buffer) a box must lie beyond the pyramid
GROUP = 64  # cull.glsl's local size
# cull.glsl's BuildingBox; draw: vertex count, first vertex, building index
BOX_DTYPE = np.dtype([("lo", "f4", 4), ("hi", "f4", 4), ("draw", "u4", 4)])
COMMAND_WORDS = 5  # count, instanceCount, first, baseInstance; moderngl draws with a 20-byte stride


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
    if pyramid is not None and viewport is not None:
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
