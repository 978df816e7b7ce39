"""Baking a tree species' impostor atlas (layout and twin: trees/_impostor_atlas.py) by drawing its full
mesh offscreen once per view, with the tree programs' BAKE variants; the atlas is cached on disk
by a hash of everything it is made from (relief.cached_arrays), since baking takes a second or
two on a software rasteriser."""

from __future__ import annotations

import hashlib

import moderngl
import numpy as np

from ..gl import RenderTarget, create_buffer, set_uniforms, shader_source, upload_texture
from ..relief import cached_arrays
from ._generator import TreeMesh
from ._impostor_atlas import (
    BAKE_SUPERSAMPLE,
    FRAME_PIXELS,
    FRAMES,
    ImpostorAtlas,
    downsample_views,
    frame_basis,
    frame_direction,
    view_space_normals,
)

BAKE_SHADERS = ("trees/trunk.glsl", "trees/leaves.glsl", "trees/bark.glsl", "trees/bake.glsl", "trees/instance.glsl")
ATLAS_VERSION = 2


def bounding_sphere(mesh: TreeMesh) -> tuple[np.ndarray, float]:
    """(centre, radius) in model space of every vertex of the mesh, leaf cards at any turn."""
    cards = mesh.cards[:, :3], mesh.cards[:, 5] * np.sqrt(2.0)
    points = [mesh.branches[:, :3], mesh.fronds[:, :3], cards[0]]
    every = np.concatenate([p for p in points if len(p)])
    centre = (every.min(axis=0) + every.max(axis=0)) / 2
    reach = np.linalg.norm(every - centre, axis=1)
    reach[len(every) - len(cards[0]) :] += cards[1]
    return centre, float(reach.max())


def view_projection(direction: np.ndarray, centre: np.ndarray, radius: float) -> np.ndarray:
    """Orthographic view of the bounding sphere from `direction`: x along frame_basis's right, y
    along its up, depth 0 at the sphere's near side and 1 at its far side."""
    right, up = frame_basis(direction)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = right / radius, up / radius, -direction / radius
    m[:3, 3] = -m[:3, :3] @ centre
    return m


def bake_atlas(ctx, mesh_parts: dict, textures, species, centre, radius) -> dict[str, np.ndarray]:
    """Every view of one tree: `mesh_parts` maps "trunks", "leaves", "fronds" to (a call that draws
    the part, its BAKE program), `textures(program, part)` binds a part's textures. Returns the
    atlas's `color` and `surface` arrays (trees.downsample_views)."""
    side = FRAMES * FRAME_PIXELS * BAKE_SUPERSAMPLE
    target = RenderTarget(ctx, (side, side), (("f4", 4), ("f4", 4), ("f4", 4)))
    target.use()
    target.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<"
    ctx.disable(moderngl.CULL_FACE)
    ctx.disable(moderngl.BLEND)
    view_pixels = FRAME_PIXELS * BAKE_SUPERSAMPLE
    for i in range(FRAMES):
        for j in range(FRAMES):
            direction = frame_direction((i, j))
            right, up = frame_basis(direction)
            target.fbo.viewport = (i * view_pixels, j * view_pixels, view_pixels, view_pixels)
            for part, (vao, program) in mesh_parts.items():
                values = dict(u_view_proj=view_projection(direction, centre, radius), u_wind=np.zeros(3))
                if part == "trunks":
                    values.update(u_bark_layer=float(species.bark_layer))
                else:
                    values.update(u_bake_dir=direction, u_normal_bias=0.0)
                    if part == "leaves":
                        values.update(u_card_right=right, u_card_up=up, u_card_shift=np.zeros(3))
                set_uniforms(program, **values)
                textures(program, part)
                vao()
    views = [target.read(k)[::-1].astype(np.float32) for k in range(3)]  # row 0 at v = 0, as the atlas
    target.release()
    views[1][..., :3] = view_space_normals(views[1][..., :3])
    color, surface = downsample_views(views[0], views[1], views[2][..., 0], BAKE_SUPERSAMPLE)
    return {"color": color, "surface": surface}


def atlas_key(mesh: TreeMesh, texture_arrays) -> str:
    """A hash of the mesh, the textures it samples, the bake's shaders and the atlas's layout."""
    digest = hashlib.sha256(repr((ATLAS_VERSION, FRAMES, FRAME_PIXELS, BAKE_SUPERSAMPLE)).encode())
    for array in (mesh.branches, mesh.branch_indices, mesh.cards, mesh.card_indices, mesh.fronds, mesh.frond_indices):
        digest.update(np.ascontiguousarray(array).tobytes())
    for array in texture_arrays:
        digest.update(np.ascontiguousarray(array).tobytes())
    for path in BAKE_SHADERS:
        digest.update(shader_source(path).encode())
    return digest.hexdigest()[:32]


class GPUImpostor:
    """One species' atlas on the GPU, and the instance buffer of its cards (grown to the cards drawn)."""

    def __init__(self, ctx, atlas: ImpostorAtlas, instance_bytes: int):
        self.atlas = atlas
        self.color = upload_texture(ctx, atlas.color, "stored", repeat=False)
        self.surface = upload_texture(ctx, atlas.surface, "stored", dtype="f1", repeat=False)
        self.instances = create_buffer(ctx, reserve=instance_bytes)
        self.count = 0

    def uniforms(self) -> dict:
        return dict(u_frames=float(FRAMES), u_impostor_centre=self.atlas.centre, u_impostor_radius=self.atlas.radius)

    def release(self):
        for obj in (self.color, self.surface, self.instances):
            obj.release()


def cached_atlas(name: str, key: str, build) -> dict[str, np.ndarray]:
    return cached_arrays(f"impostor-{name}", key, ("color", "surface"), build)
