"""Full-screen passes: one triangle made from gl_VertexID by shaders/common/fullscreen.glsl, drawn
through a vertex array made once per program (not once per frame)."""

from __future__ import annotations

import moderngl

from ._resources import resources


def draw_fullscreen(program: moderngl.Program):
    """Draws the full-screen triangle with `program` into the bound framebuffer."""
    vaos = resources(program.ctx).vertex_arrays
    vaos.get(("fullscreen", id(program)), program, []).render(moderngl.TRIANGLES, vertices=3)
