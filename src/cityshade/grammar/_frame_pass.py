"""The paper's deferred grammar evaluation (§4) as a pass of the city's frame.

A cheap pass draws every building into a G-buffer (facade uv, scope size, seed, start rule,
normal); one full-screen pass then evaluates the grammar once per grammar-facade pixel and stores
the lit colour, the glass flag and the label. The building pass reads them back at its own pixel
(GRAMMAR_DEFERRED in shaders/grammar/building.glsl) and continues into the rooms behind the glass.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import RenderTarget, bind_textures, draw_fullscreen
from ._gpu import GrammarTextures, shader_defines

G_BUFFER = (("f4", 4), ("f4", 4), ("f2", 4))  # uv + scope size; seed, start rule, building + 1; normal
RESULT = (("f2", 4), ("u4", 4))  # lit colour; glass, label


class DeferredGrammarPass:
    """Targets of the pass, remade when the frame size changes."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.size = None
        self.gbuffer = self.result = None

    def targets(self, size) -> tuple[RenderTarget, RenderTarget]:
        if size != self.size:
            self.release()
            self.gbuffer = RenderTarget(self.ctx, size, G_BUFFER)
            self.result = RenderTarget(self.ctx, size, RESULT)
            self.size = size
        return self.gbuffer, self.result

    def draw_gbuffer(self, f, grammar: GrammarTextures, set_uniforms):
        """The cheap first step for frame `f` (render._frame.FrameInputs), into the bound G-buffer."""
        program = f.gpu.programs.get("grammar/city.glsl", shader_defines())
        set_uniforms(program, u_view_proj=f.view.view_projection)
        grammar.bind(program)
        f.draw_buildings(program)  # culled like the buildings pass

    def evaluate(self, f, grammar: GrammarTextures, set_uniforms):
        """The full-screen evaluation into the bound result target, reading the G-buffer."""
        gbuffer = self.gbuffer
        program = f.gpu.programs.get(
            "grammar/deferred.glsl",
            {**shader_defines(), "BUILDING_LOD": f.view.settings.building_lod, "NO_SHADOWS": f.gpu.shadows is None},
        )
        set_uniforms(program, u_viewport=np.array(f.view.size, dtype=float))
        if f.gpu.shadows is not None:
            f.gpu.shadows.bind(program)  # the facades receive the cascaded shadows
        grammar.bind(program)
        f.gpu.city.records.bind_to_storage_buffer(0)  # the buildings' attributes for conditions
        bind_textures(
            program, dict(zip(("u_scope", "u_rule", "u_normal", "u_depth"), (*gbuffer.colors, gbuffer.depth)))
        )
        draw_fullscreen(program)

    def bind_results(self, program):
        """The building pass's inputs: lit colour and (glass, label). Nothing before the pass first
        ran (the id pass evaluates the grammar itself)."""
        if self.result is None:
            return
        bind_textures(program, dict(zip(("u_grammar_deferred_color", "u_grammar_deferred_ids"), self.result.colors)))

    def release(self):
        for target in (self.gbuffer, self.result):
            if target is not None:
                target.release()
        self.gbuffer = self.result = None
