"""Detail maps from a facade grammar: the grammar's numpy evaluator rasterised at texel centres,
each terminal given the depth and material of its semantic label (glass texels of a terminal
sink to the glass depth)."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ..assets import LABELS, tile_array
from ..grammar import compile_grammars, load
from ..grammar import evaluate, seed_vector
from ._layout import CORNICE, DEPTH_UNIT, DOOR_D, FRAME, FRAME_D, GLASS, GLASS_D, SILL, STONE, WALL, WALL_D, WOOD
from ._maps import DetailMaps

# label -> (depth in cm behind the outermost surface, material)
LABEL_RELIEF = {
    "none": (WALL_D, WALL),
    "wall": (WALL_D, WALL),
    "window": (FRAME_D, FRAME),
    "door": (DOOR_D, WOOD),
    "balcony": (SILL, STONE),
    "shop": (FRAME_D, FRAME),
    "roof": (CORNICE, STONE),
    "room": (GLASS_D, GLASS),
    "cornice": (CORNICE, STONE),
}
_DEPTH = np.array([LABEL_RELIEF[name][0] for name in LABELS], np.uint16)
_MATERIAL = np.array([LABEL_RELIEF[name][1] for name in LABELS], np.uint16)


def grammar_maps(
    path: Path,
    rule: str | None,
    facade: tuple[float, float],
    texel: float,
    seed: int = 1,
    on_rows: Callable[[int], None] | None = None,
) -> DetailMaps:
    """D and M of a grammar facade `facade` metres wide and high; on_rows(n) reports progress."""
    grammar = load(path)
    if rule is not None:
        grammar.rule(rule)
    compiled = compile_grammars({"g": grammar})
    start = compiled.address("g", rule)
    cols, rows = max(1, round(facade[0] / texel)), max(1, round(facade[1] / texel))
    tiles = tile_array(128)
    x = (np.arange(cols, dtype=np.float32) + 0.5) * texel
    label = np.empty((rows, cols), np.int64)
    glass = np.empty((rows, cols), bool)
    chunk = max(1, 20000 // cols)
    for r0 in range(0, rows, chunk):
        y = (np.arange(r0, min(rows, r0 + chunk), dtype=np.float32) + 0.5) * texel
        uv = np.stack(np.meshgrid(x, y), axis=-1).reshape(-1, 2)
        result = evaluate(compiled, start, uv, facade, seed_vector(seed), tiles)
        label[r0 : r0 + len(y)] = result.label.reshape(len(y), cols)
        glass[r0 : r0 + len(y)] = result.glass.reshape(len(y), cols)
        if on_rows:
            on_rows(len(y))
    depth = np.where(glass, GLASS_D, _DEPTH[label]).astype(np.uint16)
    material = np.where(glass, GLASS, _MATERIAL[label]).astype(np.uint16)
    return DetailMaps(depth, material, texel, DEPTH_UNIT)
