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

from ..frame import Frame, GLState, Pass, Target
from ..gl import RenderTarget, bind_textures, binding, draw_fullscreen, set_uniforms
from ._cache import GrammarPageCache, cache_defines
from ._gpu import GrammarTextures, shader_defines

G_BUFFER = (("f4", 4), ("f4", 4), ("f2", 4))  # uv + scope size; seed, facade.level, building + 1; normal
PAGES = (("u4", 4),)  # with the cache: the page key and the face's size (grammar/cache.glsl)
# lit colour; flags, the relief's opening, colour and label, the window's centre; the opening's scope
RESULT = (("f2", 4), ("u4", 4), ("f4", 4))
RGBA32F = 0x8814  # GL_RGBA32F: the opening's scope is read as an image (the buildings pass's samplers are all taken)


class DeferredGrammarPass:
    """The pass's page cache, kept across frames and sizes (its targets are the frame's)."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.cache: GrammarPageCache | None = None

    def keep_cache(self, cache_pages: int | None):
        """The cache of `cache_pages` pages (the atlas's page count; None: no cache)."""
        if self.cache is not None and self.cache.pages != cache_pages:
            self.cache.release()
            self.cache = None
        if cache_pages is not None and self.cache is None:
            self.cache = GrammarPageCache(self.ctx, cache_pages)

    def cached(self, f: Frame) -> bool:
        return f.view.settings.grammar_cache and self.cache is not None

    def draw_gbuffer(self, f: Frame, grammar: GrammarTextures):
        """The cheap first step, into the bound G-buffer."""
        cache = cache_defines() if self.cached(f) else {}
        program = f.programs.get("grammar/city.glsl", {**shader_defines(), **cache, "GRAMMAR_CACHE": bool(cache)})
        set_uniforms(program, u_view_proj=f.view.view_projection)
        grammar.bind(program)
        f.draw_buildings(program)  # culled like the buildings pass

    def update_cache(self, f: Frame, grammar: GrammarTextures):
        """The pages the G-buffer asks for made resident, as many as the cache's budget allows."""
        self.cache.update(f, grammar, f.targets[GBUFFER.name].read(len(G_BUFFER)))

    def evaluate(self, f: Frame, grammar: GrammarTextures):
        """The full-screen evaluation into the bound result target, reading the G-buffer."""
        gbuffer = f.targets[GBUFFER.name]
        program = f.programs.get(
            "grammar/deferred.glsl",
            {
                **shader_defines(),
                **(cache_defines() if self.cached(f) else {}),
                "GRAMMAR_CACHE": self.cached(f),
                "BUILDING_LOD": f.view.settings.building_lod,
                "NO_SHADOWS": f.shadows is None,
                "RELIEF_OFF": not f.view.settings.relief,
            },
        )
        set_uniforms(program, u_viewport=np.array(f.view.size, dtype=float))
        f.city.relief.bind_openings(program)  # which terminals and holes the relief recesses
        if f.view.settings.building_lod:
            f.city.bind_lod_colours()  # which buildings' cheap colours are ready
        if self.cached(f):
            self.cache.bind(program)
            bind_textures(program, {"u_page": gbuffer.colors[len(G_BUFFER)]})
        if f.shadows is not None:
            f.shadows.bind(program)  # the facades receive the cascaded shadows
        grammar.bind(program)
        f.city.records.bind_to_storage_buffer(binding("Buildings"))  # the buildings' attributes for conditions
        bind_textures(
            program, dict(zip(("u_scope", "u_rule", "u_normal", "u_depth"), (*gbuffer.colors[:3], gbuffer.depth)))
        )
        draw_fullscreen(program)

    def release(self):
        if self.cache is not None:
            self.cache.release()
            self.cache = None


GBUFFER = Target("grammar g-buffer", G_BUFFER)
GBUFFER_CACHED = Target("grammar g-buffer", G_BUFFER + PAGES)
EVALUATED = Target("grammar result", RESULT)
NONE = (0.0, 0.0, 0.0, 0.0)


def bind_grammar_results(f: Frame, program: moderngl.Program):
    """The building pass's inputs: lit colour, the ids (glass, label, the relief's opening) and
    the opening's scope. Nothing before the evaluation first ran (the id pass evaluates the grammar
    itself)."""
    result: RenderTarget | None = f.targets.get(EVALUATED.name)
    if result is None:
        return
    color, ids, opening = result.colors
    bind_textures(program, {"u_grammar_deferred_color": color, "u_grammar_deferred_ids": ids})
    if "u_grammar_deferred_opening" in program:  # an image (shaders/relief/building.glsl)
        opening.bind_to_image(binding("u_grammar_deferred_opening"), read=True, write=False, format=RGBA32F)


def _grammar(f: Frame) -> tuple[DeferredGrammarPass, GrammarTextures]:
    deferred, grammar = f.technique(DeferredGrammarPass), f.technique(GrammarTextures)
    if deferred is None or grammar is None:
        raise RuntimeError("a deferred grammar pass in a frame without the grammars' textures")
    return deferred, grammar


def grammar_gbuffer(f: Frame):
    deferred, grammar = _grammar(f)
    deferred.draw_gbuffer(f, grammar)


def grammar_cache_update(f: Frame):
    """The pages of the grammar cache this frame's G-buffer asks for (grammar._cache)."""
    deferred, grammar = _grammar(f)
    deferred.update_cache(f, grammar)


def grammar_evaluation(f: Frame):
    """Facade grammars evaluated once per pixel from the G-buffer (Krecklau §4)."""
    deferred, grammar = _grammar(f)
    deferred.evaluate(f, grammar)


def grammar_passes(city: tuple[str, ...], cache: bool, shadows: tuple[str, ...]) -> list[Pass]:
    """Krecklau §4: a G-buffer of the buildings (`city` names their inputs), then one full-screen
    grammar evaluation per pixel, shadowed if `shadows` names the maps; with `cache`, between them,
    the pages the G-buffer names evaluated once per texel into the cache's atlas."""
    textures = ("grammar textures",)
    gbuffer = GBUFFER_CACHED if cache else GBUFFER
    passes = [Pass("grammar g-buffer", grammar_gbuffer, (*city, *textures), gbuffer, clear=NONE)]
    off = GLState(depth_test=False)
    if cache:
        passes.append(Pass("grammar cache update", grammar_cache_update, (gbuffer, *textures), "grammar cache", off))
    passes.append(
        Pass("grammar evaluation", grammar_evaluation, (gbuffer, *textures, *shadows), EVALUATED, off, clear=NONE)
    )
    return passes
