"""Grammar facades on the city's buildings: the building styles that take a library style, and the
compiled library (the choice per building is render._facades.choose_facade)."""

from __future__ import annotations

from functools import lru_cache

from . import load_library
from ._compiler import CompiledGrammars, compile_grammars
from ._fit import min_width

FACADE_GRAMMAR = 1  # the record's facade.x for grammar facades (shaders/grammar/building.glsl)

# A building's style number -> library style. Styles not listed (0, the default, among them)
# keep the window-bay facade; relief facades take precedence on box buildings of their styles.
BUILDING_STYLES = {1: "office", 3: "classical", 4: "brick", 5: "shops", 6: "dusk", 7: "fig12"}
GRAMMAR_SHAPES = ("prism", "cylinder")  # domes keep the window-bay facade


@lru_cache(maxsize=1)
def library_texture() -> CompiledGrammars:
    """Every library style compiled into one texture (shared by all buildings)."""
    return compile_grammars(load_library())


@lru_cache(maxsize=1)
def library_min_widths() -> dict[str, float]:
    """Per library style, the narrowest face it fits (metres, _fit.py)."""
    return {style: min_width(grammar) for style, grammar in load_library().items()}
