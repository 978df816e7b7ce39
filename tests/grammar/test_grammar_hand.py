"""Small grammars whose terminal per pixel is worked out by hand from the rules (the scope
arithmetic of docs/grammar.md), not from the compiled texture, and compared with both the GPU
evaluator and the numpy twin: a compiler bug that both evaluators read the same way shows here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cityshade.assets import tile_array
from cityshade.grammar import FacadeRenderer, GrammarTextures, compile_grammars, evaluate_facade, loads, seed_vector
from grammar_compare import ctx  # noqa: F401  (ctx is a fixture)

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FACADE = (16.0, 12.0)
SIZE = (64, 48)
COLOURS = "".join(f"{n}->Mat(Color, 0, 0.{k + 1}, 0.5, 0.5, 1)\n" for k, n in enumerate("ABCDEF"))


def split(position: np.ndarray, total: float, parts: list[tuple[str, float]]) -> np.ndarray:
    """Index of the part of SplitX/SplitY covering each position (eq. 1: absolute parts keep their
    size, relative parts share the rest in proportion)."""
    absolute = sum(size for kind, size in parts if kind == "Abs")
    relative = sum(size for kind, size in parts if kind == "Rel")
    widths = [size if kind == "Abs" else (total - absolute) * size / relative for kind, size in parts]
    return np.searchsorted(np.cumsum(widths), position, side="right")


def by_hand(case: str, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The rule name (as an object array) of the terminal at facade points (x, y) in metres, y up."""
    width, height = FACADE
    if case == "split":
        # S->SplitX(Abs 2.5 A, Rel 1 Col, Rel 2 B, Abs 1.2 C); Col->SplitY(Rel 1 D, Abs 3 E, Rel 0.5 F)
        column = split(x, width, [("Abs", 2.5), ("Rel", 1), ("Rel", 2), ("Abs", 1.2)])
        row = split(y, height, [("Rel", 1), ("Abs", 3), ("Rel", 0.5)])
        return np.where(column == 1, np.array(list("DEF"), object)[row], np.array(list("A?BC"), object)[column])
    # S->RepeatX(1.7, Col); Col->RepeatY(2.3, Cell); Cell->SplitX(Rel 1 A, Rel 1 B): the nearest
    # whole number of parts, max(1, floor(S / size + 0.5)): 16 / 1.7 = 9.4 -> 9
    tile_x = width / max(1, math.floor(width / 1.7 + 0.5))
    local_x = np.mod(x, tile_x) / tile_x
    return np.where(local_x < 0.5, "A", "B").astype(object)


CASES = {
    "split": "S->SplitX(Abs, 2.5, A, Rel, 1, Col, Rel, 2, B, Abs, 1.2, C)\n"
    "Col->SplitY(Rel, 1, D, Abs, 3, E, Rel, 0.5, F)\n" + COLOURS,
    "repeat": "S->RepeatX(1.7, Col)\nCol->RepeatY(2.3, Cell)\nCell->SplitX(Rel, 1, A, Rel, 1, B)\n" + COLOURS,
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_terminals_match_the_rules_worked_by_hand(ctx, case):  # noqa: F811 (fixture)
    grammars = {case: loads(CASES[case], f"<{case}>")}
    compiled = compile_grammars(grammars)
    names = {compiled.address(case, n): n for n in "ABCDEF"}
    width, height = FACADE
    columns, rows = SIZE
    x = (np.arange(columns) + 0.5) / columns * width
    y = height - (np.arange(rows) + 0.5) / rows * height  # image row 0 at the top
    expected = by_hand(case, *np.meshgrid(x, y))
    tiles = tile_array(32)
    start = compiled.address(case)
    cpu = evaluate_facade(compiled, start, FACADE, SIZE, seed_vector(1), tiles)
    textures = GrammarTextures(ctx, compiled, tiles)
    _, ids = FacadeRenderer(ctx, textures, nearest=True).render(start, FACADE, SIZE, seed_vector(1))
    textures.release()
    for label, terminal in (("numpy twin", cpu.terminal), ("GPU", ids[..., 0].astype(np.int64) - 1)):
        got = np.vectorize(lambda t: names.get(int(t), "?"), otypes=[object])(terminal)
        # pixels whose centre lies within half a pixel of a hand-computed border may round either way
        differ = got != expected
        print(f"{case}, {label}: {differ.sum()} of {differ.size} pixels differ from the hand-worked terminals")
        assert differ.mean() < 0.02, f"{label}: {differ.sum()} pixels differ"
