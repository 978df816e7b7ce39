"""Grammar facades on the city's buildings: which style a building gets, and its record fields."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from . import load_library
from ._compiler import CompiledGrammars, compile_grammars
from ._random import seed_cells

FACADE_GRAMMAR = 1  # the record's facade.x for grammar facades (shaders/grammar/building.glsl)

# A building's style number -> library style. Styles not listed (0, the default, among them)
# keep the window-bay facade.
BUILDING_STYLES = {1: "office", 3: "classical", 4: "brick", 5: "shops", 6: "dusk", 7: "fig12"}
GRAMMAR_SHAPES = ("prism", "cylinder")  # domes keep the window-bay facade


@lru_cache(maxsize=1)
def library_texture() -> CompiledGrammars:
    """Every library style compiled into one texture (shared by all buildings)."""
    return compile_grammars(load_library())


def assign_facades(records: np.ndarray, masses) -> int:
    """Fills records['facade'] = (FACADE_GRAMMAR, start rule, seed cells) for grammar buildings;
    returns how many buildings got a grammar facade."""
    compiled = library_texture()
    chosen = [(i, BUILDING_STYLES[m.style]) for i, m in enumerate(masses)
              if m.style in BUILDING_STYLES and m.shape in GRAMMAR_SHAPES]
    if not chosen:
        return 0
    rows = np.array([i for i, _ in chosen])
    records["facade"][rows, 0] = FACADE_GRAMMAR
    records["facade"][rows, 1] = [compiled.address(style) for _, style in chosen]
    records["facade"][rows, 2:] = seed_cells([masses[i].seed for i in rows])
    return len(rows)
