"""Grammar facades over a whole city, by either path of §4, for the facade benchmark:

forward   depth prepass, then the buildings again with the grammar evaluated where the depth
          test passes (once per visible pixel);
deferred  the paper's pipeline: a cheap pass writes facade uv, scope size, seed, start rule and
          normal; one full-screen pass evaluates the grammar.

Both end with Phong lighting and the same screen-space ambient occlusion pass.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..assets import TileArray
from ..gl import FRAME_BLOCK, RenderTarget, VertexArrays, bind_textures, create_buffer, draw_fullscreen, set_uniforms
from ..gl import programs as gl_programs
from ..scene import VERTEX_ATTRIBUTES, VERTEX_FORMAT, Camera, batch
from ._city import FACADE_GRAMMAR
from ._compiler import CompiledGrammars
from ._gpu import GrammarTextures, shader_defines
from ._random import seed_cells

PATHS = ("forward", "deferred")
# The faster path as measured by `cityshade bench facades` (llvmpipe, 20,000 buildings at 1024x768:
# deferred / forward = 0.68 as the geometric mean over the grammars and views; 0.62 in the city frame).
DEFAULT_PATH = "deferred"
SUN = np.array([0.45, 0.75, 0.35])
SKY = (0.3, 0.42, 0.62)  # linear


class FacadeCityRenderer:
    """Every building of `masses` gets the grammar at rule address `start` (seeded per building)."""

    def __init__(self, ctx: moderngl.Context, masses, compiled: CompiledGrammars, tiles: TileArray,
                 size: tuple[int, int]):
        self.ctx = ctx
        self.size = tuple(size)
        vertices, records = batch(masses)
        records["facade"][:, 0] = FACADE_GRAMMAR
        records["facade"][:, 2:] = seed_cells([m.seed for m in masses])
        self.records = records
        self.vbo = create_buffer(ctx, vertices)
        self.ssbo = create_buffer(ctx, records)
        self.textures = GrammarTextures(ctx, compiled, tiles)
        programs = gl_programs(ctx)
        defines = shader_defines()
        self.programs = {
            "depth": programs.get("grammar/city.glsl", {**defines, "DEPTH_ONLY": True}),
            "forward": programs.get("grammar/city.glsl", {**defines, "FORWARD": True}),
            "gbuffer": programs.get("grammar/city.glsl", {**defines, "GBUFFER": True}),
            "deferred": programs.get("grammar/deferred.glsl", {**defines, "NO_SHADOWS": True}),
            "ssao": programs.get("grammar/ssao.glsl"),
        }
        self.vaos = VertexArrays(ctx)
        self.lit = RenderTarget(ctx, self.size, (("f2", 4),))
        self.gbuffer = RenderTarget(ctx, self.size, (("f4", 4), ("f4", 4), ("f2", 4)))
        self.output = RenderTarget(ctx, self.size, (("f1", 4),))
        self.start = -1

    def _vao(self, name: str):
        return self.vaos.get(name, self.programs[name], [(self.vbo, VERTEX_FORMAT, *VERTEX_ATTRIBUTES)])

    def set_grammar(self, start: int):
        if start != self.start:
            self.records["facade"][:, 1] = start
            self.ssbo.write(self.records.tobytes())
            self.start = start

    def _frame_block(self, camera: Camera):
        FRAME_BLOCK.write(self.ctx, u_inv_view_proj=np.linalg.inv(self._view_projection(camera)), u_camera=camera.eye,
                          u_time=0.0, u_sun_dir=SUN / np.linalg.norm(SUN), u_exposure=1.0,
                          u_sun_color=np.array([2.6, 2.4, 2.1]), u_sky_ambient=np.array([0.45, 0.5, 0.6]),
                          u_ground_ambient=np.array([0.2, 0.18, 0.16]))

    def _view_projection(self, camera: Camera) -> np.ndarray:
        return camera.view_projection(self.size[0] / self.size[1])

    def _uniforms(self, program, camera: Camera):
        set_uniforms(program, u_view_proj=self._view_projection(camera))
        self.textures.bind(program)

    def _buildings(self, name: str, camera: Camera):
        program = self.programs[name]
        self._uniforms(program, camera)
        self.ssbo.bind_to_storage_buffer(0)
        self._vao(name).render(moderngl.TRIANGLES)

    def draw(self, camera: Camera, path: str = DEFAULT_PATH):
        """One frame by `path`; the tone-mapped result is in self.output."""
        ctx = self.ctx
        self._frame_block(camera)
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        if path == "forward":
            self.lit.use()
            self.lit.fbo.clear(*SKY, 1.0, depth=1.0)
            ctx.depth_func = "<"
            ctx.color_mask = (False, False, False, False)
            self._buildings("depth", camera)
            ctx.color_mask = (True, True, True, True)
            ctx.depth_func = "<="
            self._buildings("forward", camera)
            depth = self.lit.depth
        else:
            self.gbuffer.use()
            self.gbuffer.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
            ctx.depth_func = "<"
            self._buildings("gbuffer", camera)
            self.lit.use()
            self.lit.fbo.clear(*SKY, 1.0, depth=1.0)
            ctx.disable(moderngl.DEPTH_TEST)
            program = self.programs["deferred"]
            self.textures.bind(program)  # the camera comes from the frame block
            self.ssbo.bind_to_storage_buffer(0)  # the buildings' attributes for conditions
            bind_textures(program, dict(zip(("u_scope", "u_rule", "u_normal", "u_depth"),
                                            (*self.gbuffer.colors, self.gbuffer.depth))))
            program["u_viewport"] = tuple(float(x) for x in self.size)
            draw_fullscreen(self.programs["deferred"])
            depth = self.gbuffer.depth
        self._ssao(camera, depth)

    def _ssao(self, camera: Camera, depth):
        ctx = self.ctx
        self.output.use()
        ctx.disable(moderngl.DEPTH_TEST)
        program = self.programs["ssao"]
        bind_textures(program, {"u_color": self.lit.colors[0], "u_depth": depth})
        program["u_near_far"] = (camera.near, camera.far)
        program["u_pixels_per_metre"] = self.size[1] / (2 * np.tan(np.radians(camera.fov_y) / 2))
        draw_fullscreen(self.programs["ssao"])

    def read(self) -> np.ndarray:
        return self.output.read(0)[..., :3].copy()

    def release(self):
        for target in (self.lit, self.gbuffer, self.output):
            target.release()
        self.vaos.release()
        self.vbo.release()
        self.ssbo.release()
        self.textures.release()
