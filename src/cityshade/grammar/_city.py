"""Grammar facades on the city's buildings: the building styles that take a library style, and the
compiled library (the choice per building is render._facades.choose_facade)."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from ..errors import UsageError
from . import load, load_library
from ._compiler import CompiledGrammars, compile_grammars
from ._fit import min_width

FACADE_GRAMMAR = 1  # the record's facade.x for grammar facades (shaders/grammar/building.glsl)

# A building's style number -> library style. Styles not listed (0, the default, among them)
# keep the window-bay facade; relief facades take precedence on box buildings of their styles.
BUILDING_STYLES = {1: "office", 3: "classical", 4: "brick", 5: "shops", 6: "dusk", 7: "fig12"}
GRAMMAR_SHAPES = ("prism", "cylinder", "dome")  # a dome's rings are faces (scene/_dome_faces.py)


@lru_cache(maxsize=1)
def library_texture() -> CompiledGrammars:
    """Every library style compiled into one texture (shared by all buildings)."""
    return compile_grammars(load_library())


@lru_cache(maxsize=None)  # a city's faces start at a few levels
def library_min_widths(level: int = 0) -> dict[str, float]:
    """Per library style, the narrowest face at facade.level `level` it fits (metres, _fit.py)."""
    return {style: min_width(grammar, level) for style, grammar in load_library().items()}


def library_texture_with(files: tuple[str, ...]) -> CompiledGrammars:
    """The library styles, then the grammars of `files` (named by file stem), in one texture. The
    compiler places rules in order and only reuses earlier addresses, so the library styles keep the
    addresses of library_texture() that the buildings' records hold."""
    if not files:
        return library_texture()
    grammars = load_library()
    for path in files:
        name = Path(path).stem
        if name in grammars:
            raise UsageError(f"grammar file {path}: {name!r} is already a style of the library; rename the file")
        grammars[name] = load(path)
    return compile_grammars(grammars)
