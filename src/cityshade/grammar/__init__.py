"""Procedural facade grammars (Krecklau & Kobbelt 2011): parse, check, compile to one texture,
evaluate per pixel (GPU shader and numpy reference)."""

from __future__ import annotations

from pathlib import Path

from ..assets import TILE_INDEX
from ._checks import Grammar, Rule, TexRef, check, costs
from ._compiler import CompiledGrammars, compile_grammars
from ._diagnostics import Diagnostic, GrammarError, Location
from ._loader import SourceGrammar, library_path, load_source, parse_string

# The facade styles of the library (bays.grammar is a building block they include; simple.grammar
# is fig. 12 with its random choices fixed, the "simple" grammar of the benchmark).
LIBRARY_STYLES = ("fig12", "brick", "classical", "office", "shops", "dusk", "storeys")


def load(path: str | Path) -> Grammar:
    """Parses and checks a grammar file (and the files it uses)."""
    return check(load_source(path), TILE_INDEX)


def loads(text: str, name: str = "<string>") -> Grammar:
    """Parses and checks grammar text."""
    return check(parse_string(text, name), TILE_INDEX)


def load_library() -> dict[str, Grammar]:
    """The bundled facade styles, by name."""
    return {style: load(library_path(f"{style}.grammar")) for style in LIBRARY_STYLES}


# the city's facades need load_library above
from ._cga import CgaError, translate  # noqa: E402
from ._city import (  # noqa: E402
    BUILDING_STYLES,
    FACADE_GRAMMAR,
    GRAMMAR_SHAPES,
    library_min_widths,
    library_texture,
    library_texture_with,
)
from ._fit import min_width  # noqa: E402
from ._frame_pass import DeferredGrammarPass, bind_grammar_results, grammar_passes  # noqa: E402
from ._gpu import FacadeRenderer, GrammarTextures, shader_defines  # noqa: E402
from ._random import FACADE_INDICES, facade_seed_vector, seed_cells, seed_vector  # noqa: E402
from ._reference import CPU_BYTES_PER_PIXEL, evaluate, evaluate_facade, hole_cut  # noqa: E402

__all__ = [
    "BUILDING_STYLES",
    "FACADE_GRAMMAR",
    "GRAMMAR_SHAPES",
    "library_texture",
    "library_texture_with",
    "seed_cells",
    "seed_vector",
    "CPU_BYTES_PER_PIXEL",
    "evaluate",
    "evaluate_facade",
    "CgaError",
    "translate",
    "FacadeRenderer",
    "hole_cut",
    "DeferredGrammarPass",
    "bind_grammar_results",
    "grammar_passes",
    "GrammarTextures",
    "shader_defines",
    "Grammar",
    "Rule",
    "TexRef",
    "CompiledGrammars",
    "Diagnostic",
    "GrammarError",
    "Location",
    "SourceGrammar",
    "FACADE_INDICES",
    "facade_seed_vector",
    "LIBRARY_STYLES",
    "check",
    "costs",
    "compile_grammars",
    "library_path",
    "load",
    "loads",
    "load_library",
    "load_source",
    "parse_string",
    "library_min_widths",
    "min_width",
]
