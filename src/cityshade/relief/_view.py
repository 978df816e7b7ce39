"""Relief facades on the GPU, one instance per facade, and the numpy reference from the same camera.

Each instance is a facade frame (shaders/relief/frame.glsl): the world position of its lower-left
corner, the unit direction along it and its outward normal. The single test facade lies in the
world plane z = 0 with its lower-left corner at the origin, facing +z, relief going to -z, so its
map space (texels, texels, depth steps) is world space scaled by (1 / texel, 1 / texel, -1 / depth_unit).
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..gl import FRAME_BLOCK, DrawBuffers, ProgramCache, RenderTarget, create_buffer, draw_buffers, set_uniforms
from ..scene import Camera
from ._gpu import RENDERERS, GpuFacade, renderer_defines
from ._maps import DetailMaps
from ._mesh import relief_mesh
from ._reference import FACE_FRONT, FACE_NEG_X, FACE_NEG_Y, FACE_POS_X, FACE_POS_Y, MISS, Hits, trace_reference

SUN = (0.45, 0.6, 0.65)  # world, towards the sun
FRAME_DTYPE = np.dtype([("origin", "<f4", 3), ("along", "<f4", 3), ("out", "<f4", 3)])
SINGLE_FACADE = np.array([((0, 0, 0), (1, 0, 0), (0, 0, 1))], FRAME_DTYPE)
VERTEX_DTYPE = np.dtype([("pos", "<f4", 3), ("face", "<i4")])


def map_scale(maps: DetailMaps) -> np.ndarray:
    """Metres per map unit along world x, y, z."""
    return np.array([maps.texel, maps.texel, -maps.depth_unit])


def facade_camera(
    maps: DetailMaps,
    azimuth: float,
    elevation: float,
    distance: float,
    target: tuple[float, float] = (0.5, 0.5),
    fov_y: float = 40.0,
) -> Camera:
    """A camera looking at a point of the facade (target as fractions of its size) from a direction
    given in degrees: azimuth from the facade normal towards +x, elevation above the horizontal."""
    width, height = maps.size_m
    aim = np.array([target[0] * width, target[1] * height, 0.0])
    a, e = np.radians(azimuth), np.radians(elevation)
    eye = aim + distance * np.array([np.sin(a) * np.cos(e), np.sin(e), np.cos(a) * np.cos(e)])
    return Camera(tuple(eye), tuple(aim), fov_y=fov_y, near=0.05, far=10 * distance + 100)


def slab_faces(cols: int, rows: int, depth: float, sides: bool = True) -> np.ndarray:
    """Triangles of the traced volume's boundary faces with their face ids: the front quad and,
    with sides, the four side quads (the vertex shader drops those facing away from the eye).
    Facades on building walls need only the front: the building closes the sides."""
    x, y, z = (0.0, float(cols)), (0.0, float(rows)), (0.0, depth)
    quads = [(FACE_FRONT, [(x[0], y[0], 0), (x[1], y[0], 0), (x[1], y[1], 0), (x[0], y[1], 0)])]
    if sides:
        quads += [
            (FACE_NEG_X, [(0, y[0], z[0]), (0, y[1], z[0]), (0, y[1], z[1]), (0, y[0], z[1])]),
            (FACE_POS_X, [(cols, y[0], z[0]), (cols, y[1], z[0]), (cols, y[1], z[1]), (cols, y[0], z[1])]),
            (FACE_NEG_Y, [(x[0], 0, z[0]), (x[1], 0, z[0]), (x[1], 0, z[1]), (x[0], 0, z[1])]),
            (FACE_POS_Y, [(x[0], rows, z[0]), (x[1], rows, z[0]), (x[1], rows, z[1]), (x[0], rows, z[1])]),
        ]
    vertices = np.zeros(len(quads) * 6, VERTEX_DTYPE)
    for q, (face, corners) in enumerate(quads):
        for v, corner in enumerate((0, 1, 2, 0, 2, 3)):
            vertices[q * 6 + v] = (corners[corner], face)
    return vertices


@dataclass
class FacadeImages:
    color: np.ndarray  # (H, W, 3) float
    material: np.ndarray  # (H, W) int, MISS where no hit
    face: np.ndarray  # (H, W) int
    steps: np.ndarray  # (H, W) int
    point: np.ndarray  # (H, W, 3) map space, nan on a miss


class FacadeView:
    """Draws one GpuFacade with any of the six renderers into an offscreen target."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], programs: ProgramCache | None = None):
        self.ctx = ctx
        self.size = size
        self.programs = programs or ProgramCache(ctx)
        self.target = RenderTarget(ctx, size, colors=(("f2", 4), ("u4", 4), ("f4", 4)))

    def draw(self, facade: GpuFacade, camera: Camera, renderer: str, lsb_mod37: bool = False):
        """The single test facade with its side quads."""
        rows, cols = facade.maps.shape
        self.target.use()
        self.ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        draw_facades(
            self.ctx,
            self.programs,
            facade,
            camera,
            renderer,
            slab_faces(cols, rows, facade.slab_depth),
            SINGLE_FACADE,
            self.size[0] / self.size[1],
            lsb_mod37,
        )

    def read(self) -> FacadeImages:
        color = self.target.read(0)[..., :3].astype(np.float32)
        ids = self.target.read(1).astype(np.int64)
        point = self.target.read(2)[..., :3].astype(np.float64)
        hit = ids[..., 0] > 0
        point[~hit] = np.nan
        return FacadeImages(
            color, np.where(hit, ids[..., 0] - 1, MISS), np.where(hit, ids[..., 1], MISS), ids[..., 2], point
        )

    def release(self):
        self.target.release()


def trace_view(maps: DetailMaps, camera: Camera, size: tuple[int, int]) -> Hits:
    """The reference hits for every pixel centre of the view."""
    scale = map_scale(maps)
    directions = camera.pixel_rays(size) / scale
    origins = np.broadcast_to(camera.eye / scale, directions.shape)
    return trace_reference(maps, origins, directions)


def write_frame_block(ctx: moderngl.Context, camera: Camera, aspect: float):
    """The camera and the sun of the relief views; no ambient light, time or exposure."""
    FRAME_BLOCK.write(
        ctx,
        u_inv_view_proj=np.linalg.inv(camera.view_projection(aspect)),
        u_camera=camera.eye,
        u_time=0.0,
        u_sun_dir=SUN,
        u_exposure=1.0,
        u_sun_color=np.ones(3),
        u_sky_ambient=np.zeros(3),
        u_ground_ambient=np.zeros(3),
    )


def draw_facades(
    ctx: moderngl.Context,
    programs: ProgramCache,
    facade: GpuFacade,
    camera: Camera,
    renderer: str,
    vertices: np.ndarray,
    frames: np.ndarray,
    aspect: float,
    lsb_mod37: bool = False,
    depth_only: bool = False,
    tiled: bool = False,
    after_prepass: bool = False,
):
    """Draws every frame (FRAME_DTYPE) as an instance of the facade into the bound framebuffer;
    depth_only draws just the quads' depth, for a prepass, and after_prepass then traces only the
    pixels that passed it (depth writes must be off); tiled repeats the maps across quads larger
    than them."""
    defines = {**renderer_defines(renderer, lsb_mod37, tiled), "DEPTH_ONLY": depth_only, "EARLY_DEPTH": after_prepass}
    program = programs.get("relief/facade.glsl", defines)
    buffers = draw_buffers(ctx)  # rewritten each draw, made once
    quads = buffers.write("relief quads", np.ascontiguousarray(vertices, VERTEX_DTYPE))
    instances = buffers.write("relief frames", np.ascontiguousarray(frames, FRAME_DTYPE))
    vao = buffers.vertex_array(
        program.glo,
        program,
        [(quads, "3f4 i4", "in_position", "in_face"), (instances, "3f4 3f4 3f4/i", "in_origin", "in_along", "in_out")],
    )
    facade.bind(program, RENDERERS[renderer][1])
    write_frame_block(ctx, camera, aspect)
    set_uniforms(program, u_view_proj=camera.view_projection(aspect), u_map_scale=np.abs(map_scale(facade.maps)))
    ctx.enable(moderngl.DEPTH_TEST)
    vao.render(moderngl.TRIANGLES, vertices=len(vertices), instances=len(frames))


class MeshFacade:
    """The triangulated relief of a facade (the geometry baseline) in GPU buffers."""

    def __init__(self, ctx: moderngl.Context, maps: DetailMaps):
        self.maps = maps
        vertices, indices = relief_mesh(maps)
        self.triangles = len(indices) // 3
        self.vbo, self.ibo = create_buffer(ctx, vertices), create_buffer(ctx, indices)
        self.nbytes = vertices.nbytes + indices.nbytes
        self.instances = DrawBuffers(ctx)  # the frames drawn, which change with the view

    def draw(self, ctx: moderngl.Context, programs: ProgramCache, camera: Camera, frames: np.ndarray, aspect: float):
        program = programs.get("relief/mesh.glsl")
        instances = self.instances.write("frames", np.ascontiguousarray(frames, FRAME_DTYPE))
        vao = self.instances.vertex_array(
            program.glo,
            program,
            [
                (self.vbo, "3f4 i4 i4", "in_position", "in_face", "in_material"),
                (instances, "3f4 3f4 3f4/i", "in_origin", "in_along", "in_out"),
            ],
            index_buffer=self.ibo,
        )
        write_frame_block(ctx, camera, aspect)
        set_uniforms(program, u_view_proj=camera.view_projection(aspect), u_map_scale=np.abs(map_scale(self.maps)))
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.enable(moderngl.CULL_FACE)  # every quad wound counter-clockwise seen from outside
        vao.render(moderngl.TRIANGLES, vertices=3 * self.triangles, instances=len(frames))
        ctx.disable(moderngl.CULL_FACE)

    def release(self):
        self.instances.release()
        self.vbo.release()
        self.ibo.release()
