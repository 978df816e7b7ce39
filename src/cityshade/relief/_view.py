"""One relief facade on its own, on the GPU and through the numpy reference, from the same camera.

The facade lies in the world plane z = 0 with its lower-left corner at the origin, facing +z;
relief goes to -z. Map space (texels, texels, depth steps) is world space scaled by
(1 / texel, 1 / texel, -1 / depth_unit).
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..gl import ProgramCache, RenderTarget
from ..scene import Camera
from ._gpu import RENDERERS, GpuFacade, renderer_defines
from ._maps import DetailMaps
from ._reference import FACE_FRONT, FACE_NEG_X, FACE_NEG_Y, FACE_POS_X, FACE_POS_Y, MISS, Hits, trace_reference

SUN = (0.45, 0.6, 0.65)  # facade space, towards the sun


def map_scale(maps: DetailMaps) -> np.ndarray:
    """Metres per map unit along world x, y, z."""
    return np.array([maps.texel, maps.texel, -maps.depth_unit])


def facade_camera(maps: DetailMaps, azimuth: float, elevation: float, distance: float,
                  target: tuple[float, float] = (0.5, 0.5), fov_y: float = 40.0) -> Camera:
    """A camera looking at a point of the facade (target as fractions of its size) from a direction
    given in degrees: azimuth from the facade normal towards +x, elevation above the horizontal."""
    width, height = maps.size_m
    aim = np.array([target[0] * width, target[1] * height, 0.0])
    a, e = np.radians(azimuth), np.radians(elevation)
    eye = aim + distance * np.array([np.sin(a) * np.cos(e), np.sin(e), np.cos(a) * np.cos(e)])
    return Camera(tuple(eye), tuple(aim), fov_y=fov_y, near=0.05, far=10 * distance + 100)


def _slab_faces(cols: int, rows: int, depth: float, eye: np.ndarray) -> np.ndarray:
    """Triangles of the traced volume's faces that face the eye, with their face ids."""
    x, y, z = (0.0, float(cols)), (0.0, float(rows)), (0.0, depth)
    quads = []
    if eye[2] < 0:
        quads.append((FACE_FRONT, [(x[0], y[0], 0), (x[1], y[0], 0), (x[1], y[1], 0), (x[0], y[1], 0)]))
    if eye[0] < 0:
        quads.append((FACE_NEG_X, [(0, y[0], z[0]), (0, y[1], z[0]), (0, y[1], z[1]), (0, y[0], z[1])]))
    if eye[0] > cols:
        quads.append((FACE_POS_X, [(cols, y[0], z[0]), (cols, y[1], z[0]), (cols, y[1], z[1]), (cols, y[0], z[1])]))
    if eye[1] < 0:
        quads.append((FACE_NEG_Y, [(x[0], 0, z[0]), (x[1], 0, z[0]), (x[1], 0, z[1]), (x[0], 0, z[1])]))
    if eye[1] > rows:
        quads.append((FACE_POS_Y, [(x[0], rows, z[0]), (x[1], rows, z[0]), (x[1], rows, z[1]), (x[0], rows, z[1])]))
    vertices = np.zeros(len(quads) * 6, dtype=[("pos", "f4", 3), ("face", "i4")])
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
        program = self.programs.get("relief/facade.glsl", renderer_defines(renderer, lsb_mod37))
        scale = map_scale(facade.maps)
        map_to_clip = camera.view_projection(self.size[0] / self.size[1]) @ np.diag([*scale, 1.0])
        eye = camera.eye / scale
        rows, cols = facade.maps.shape
        vertices = _slab_faces(cols, rows, facade.slab_depth, eye)
        vbo = self.ctx.buffer(vertices.tobytes())
        # RM ignores the entry face, so its programs have no in_face.
        layout = (vbo, "3f4 i4", "in_position", "in_face") if "in_face" in program else (vbo, "3f4 4x", "in_position")
        vao = self.ctx.vertex_array(program, [layout])
        facade.bind(program, RENDERERS[renderer][1])
        program["uMapToClip"].write(map_to_clip.T.astype("f4").tobytes())
        for name, value in (("uEye", tuple(eye)), ("uMapScale", tuple(np.abs(scale))), ("uSunDir", SUN)):
            if name in program:
                program[name].value = value
        self.target.use()
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        vao.render(moderngl.TRIANGLES)
        vao.release()
        vbo.release()

    def read(self) -> FacadeImages:
        color = self.target.read(0)[..., :3].astype(np.float32)
        ids = self.target.read(1).astype(np.int64)
        point = self.target.read(2)[..., :3].astype(np.float64)
        hit = ids[..., 0] > 0
        point[~hit] = np.nan
        return FacadeImages(color, np.where(hit, ids[..., 0] - 1, MISS), np.where(hit, ids[..., 1], MISS),
                            ids[..., 2], point)

    def release(self):
        self.target.release()


def trace_view(maps: DetailMaps, camera: Camera, size: tuple[int, int]) -> Hits:
    """The reference hits for every pixel centre of the view."""
    scale = map_scale(maps)
    directions = camera.pixel_rays(size) / scale
    origins = np.broadcast_to(camera.eye / scale, directions.shape)
    return trace_reference(maps, origins, directions)
