"""The paper's deferred grammar evaluation (§4) as a pass of the city's frame.

A cheap pass draws every building into a G-buffer (facade uv, scope size, seed, facade.level,
normal); one full-screen pass then evaluates the grammar once per grammar-facade pixel and stores
the lit colour, the glass flag and the label, and the window opening the relief recesses there
(its index, scope and the flat grammar's colour), so the buildings pass need not evaluate again.
The building pass reads them back at its own pixel (GRAMMAR_DEFERRED in
shaders/grammar/building.glsl) and continues into the rooms behind the glass.
With the page cache (grammar._cache) the G-buffer also names the cache page each pixel needs, the
cache update evaluates missing pages, and the evaluation reads resident pages instead.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import RenderTarget, bind_textures, binding, draw_fullscreen
from ._cache import GrammarPageCache, cache_defines
from ._gpu import GrammarTextures, shader_defines

G_BUFFER = (("f4", 4), ("f4", 4), ("f2", 4))  # uv + scope size; seed, facade.level, building + 1; normal
PAGES = (("u4", 4),)  # with the cache: the page key and the face's size (grammar/cache.glsl)
# lit colour; flags, the relief's opening, colour and label, the window's centre; the opening's scope
RESULT = (("f2", 4), ("u4", 4), ("f4", 4))
RGBA32F = 0x8814  # GL_RGBA32F: the opening's scope is read as an image (the buildings pass's samplers are all taken)


class DeferredGrammarPass:
    """Targets of the pass, remade when the frame size changes."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.size = None
        self.gbuffer = self.result = None
        self.cache: GrammarPageCache | None = None  # kept across frames and sizes

    def targets(self, size, cache_pages: int | None = None) -> tuple[RenderTarget, RenderTarget]:
        """The G-buffer and result targets at `size`; with `cache_pages` (the atlas's page count)
        the G-buffer has the page attachment and the cache exists."""
        cached = cache_pages is not None
        if self.gbuffer is None or size != self.size or cached != (len(self.gbuffer.colors) > len(G_BUFFER)):
            self._release_targets()
            self.gbuffer = RenderTarget(self.ctx, size, G_BUFFER + (PAGES if cached else ()))
            self.result = RenderTarget(self.ctx, size, RESULT)
            self.size = size
        if self.cache is not None and self.cache.pages != cache_pages:
            self.cache.release()
            self.cache = None
        if cached and self.cache is None:
            self.cache = GrammarPageCache(self.ctx, cache_pages)
        return self.gbuffer, self.result

    def cached(self, f) -> bool:
        return f.view.settings.grammar_cache and self.cache is not None

    def draw_gbuffer(self, f, grammar: GrammarTextures, set_uniforms):
        """The cheap first step for frame `f` (render._frame.FrameInputs), into the bound G-buffer."""
        cache = cache_defines() if self.cached(f) else {}
        program = f.gpu.programs.get("grammar/city.glsl", {**shader_defines(), **cache, "GRAMMAR_CACHE": bool(cache)})
        set_uniforms(program, u_view_proj=f.view.view_projection)
        grammar.bind(program)
        f.draw_buildings(program)  # culled like the buildings pass

    def update_cache(self, f, grammar: GrammarTextures):
        """The pages the G-buffer asks for made resident, as many as the cache's budget allows."""
        self.cache.update(f, grammar, self.gbuffer.read(len(G_BUFFER)))

    def evaluate(self, f, grammar: GrammarTextures, set_uniforms):
        """The full-screen evaluation into the bound result target, reading the G-buffer."""
        gbuffer = self.gbuffer
        program = f.gpu.programs.get(
            "grammar/deferred.glsl",
            {
                **shader_defines(),
                **(cache_defines() if self.cached(f) else {}),
                "GRAMMAR_CACHE": self.cached(f),
                "BUILDING_LOD": f.view.settings.building_lod,
                "NO_SHADOWS": f.gpu.shadows is None,
                "RELIEF_OFF": not f.view.settings.relief,
            },
        )
        set_uniforms(program, u_viewport=np.array(f.view.size, dtype=float))
        f.gpu.city.relief.bind_openings(program)  # which terminals and holes the relief recesses
        if f.view.settings.building_lod:
            f.gpu.city.bind_lod_colours()  # which buildings' cheap colours are ready
        if self.cached(f):
            self.cache.bind(program)
            bind_textures(program, {"u_page": gbuffer.colors[len(G_BUFFER)]})
        if f.gpu.shadows is not None:
            f.gpu.shadows.bind(program)  # the facades receive the cascaded shadows
        grammar.bind(program)
        f.gpu.city.records.bind_to_storage_buffer(binding("Buildings"))  # the buildings' attributes for conditions
        bind_textures(
            program, dict(zip(("u_scope", "u_rule", "u_normal", "u_depth"), (*gbuffer.colors[:3], gbuffer.depth)))
        )
        draw_fullscreen(program)

    def bind_results(self, program):
        """The building pass's inputs: lit colour, the ids (glass, label, the relief's opening) and
        the opening's scope. Nothing before the pass first ran (the id pass evaluates the grammar
        itself)."""
        if self.result is None:
            return
        color, ids, opening = self.result.colors
        bind_textures(program, {"u_grammar_deferred_color": color, "u_grammar_deferred_ids": ids})
        if "u_grammar_deferred_opening" in program:  # an image (shaders/relief/building.glsl)
            opening.bind_to_image(binding("u_grammar_deferred_opening"), read=True, write=False, format=RGBA32F)

    def _release_targets(self):
        for target in (self.gbuffer, self.result):
            if target is not None:
                target.release()
        self.gbuffer = self.result = None

    def release(self):
        self._release_targets()
        if self.cache is not None:
            self.cache.release()
            self.cache = None
