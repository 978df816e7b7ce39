"""Overhang(before, after, Rule): a Split part drawn past its own ends over its neighbours."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cityshade.assets import LABELS, tile_array
from cityshade.grammar import GrammarError, compile_grammars, evaluate, loads
from grammar_compare import compare, ctx  # noqa: F401  (ctx is a fixture)

# Sills 0.3 m wider than their window on each side, and a cornice ledge 0.25 m over the bays.
SILLS = """\
S->SplitY(Rel, 1, Floors, Abs, 0.4, Ledge)
Floors->RepeatY(3, Floor)
Floor->RepeatX(3, Bay)
Bay->SplitY(Abs, 0.8, Wall, Abs, 0.15, SillRow, Abs, 1.5, WindowRow, Rel, 1, Wall)
SillRow->SplitX(Rel, 1, Wall, Abs, 1.2, Sill, Rel, 1, Wall)
WindowRow->SplitX(Rel, 1, Wall, Abs, 1.2, Window, Rel, 1, Wall)
Sill->Overhang(0.3, 0.3, Stone)
Stone->Color(0.85, 0.85, 0.8, cornice)
Window->Color(0.2, 0.3, 0.4, window)
Wall->Color(0.7, 0.4, 0.3)
Ledge->SplitY(Abs, 0.2, Cornice, Rel, 1, Wall)
Cornice->Color(0.9, 0.9, 0.85, cornice)
"""


def test_sills_wider_than_their_windows_gpu_matches_numpy(ctx, output_dir):
    compiled = compile_grammars({"sills": loads(SILLS)})
    size = (240, 180)  # 12 x 9 m at 20 px per metre: pixel centres never sit on a border
    cpu, _ = compare(ctx, compiled, "sills", output_dir, facade=(12.0, 9.0), size=size, allowed=0, nearest=False)
    labels = cpu.label[::-1]  # row 0 at the bottom
    cornice, window = LABELS.index("cornice"), LABELS.index("window")
    # The first floor's sill row (y 0.8-0.95 m) and window row (0.95-2.45 m).
    sill_row, window_row = labels[int(0.875 * 20)], labels[int(1.7 * 20)]
    sill_px, window_px = np.count_nonzero(sill_row == cornice), np.count_nonzero(window_row == window)
    print(f"one row: {sill_px} sill pixels over {window_px} window pixels")
    assert window_px == 4 * 24  # four 1.2 m windows
    assert sill_px == 4 * 36  # their sills, 0.3 m wider on each side, over the wall


def _column(text: str, width: float, xs: np.ndarray):
    compiled = compile_grammars({"g": loads(text)})
    uv = np.stack([xs, np.full_like(xs, 0.5)], axis=1).astype(np.float32)
    result = evaluate(compiled, compiled.address("g"), uv, (width, 1.0), (0.0, 0.0), tile_array(8))
    names = {compiled.address("g", name): name for name in "ABC"}
    return np.array([names.get(int(a), "none") for a in result.terminal])


@settings(max_examples=40, deadline=None)
@given(st.floats(0.5, 4.0), st.floats(0.2, 3.0), st.floats(0.5, 4.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_overhang_reaches_its_margins_and_nothing_else(left, middle, right, before, after):
    """Pixels outside the enlarged rectangle keep the split as it was; inside it, the overhang."""
    plain = f"S->SplitX(Abs, {left}, A, Abs, {middle}, M, Abs, {right}, B)\n"
    colours = "A->Color(1, 0, 0)\nB->Color(0, 0, 1)\nC->Color(0, 1, 0, cornice)\n"
    width = left + middle + right
    xs = np.linspace(0.005, width - 0.005, 400)
    over = _column(plain + f"M->Overhang({before}, {after}, C)\n" + colours, width, xs)
    under = _column(plain + "M->C\n" + colours, width, xs)
    lo, hi = np.float16(left).item() - np.float16(before).item(), np.float16(left).item() + np.float16(middle).item()
    hi += np.float16(after).item()
    clear = (xs < lo - 1e-3) | (xs > hi + 1e-3)  # 16-bit sizes move the ends by about a millimetre
    inside = (xs > lo + 1e-3) & (xs < hi - 1e-3)
    assert np.array_equal(over[clear], under[clear])
    assert np.all(over[inside] == "C")


@pytest.mark.parametrize(
    "text, message",
    [
        ("S->SplitX(Rel, 1, A, Rel, 1, O)\nO->Overhang(1.5, 0, A)\nA->Color(1, 0, 0)\n", "in [0, 1] metres, got 1.5"),
        ("S->SplitX(Rel, 1, A, Rel, 1, O)\nO->Overhang(0.2, -0.1, A)\nA->Color(1, 0, 0)\n", "got -0.1"),
        ("S->Layer(A, O)\nO->Overhang(0.2, 0.2, A)\nA->Color(1, 0, 0)\n", "Layer cannot hold an Overhang"),
        ("S->SplitX(Tile, 2, O)\nO->Overhang(0.2, 0.2, A)\nA->Color(1, 0, 0)\n", "SplitX cannot hold an Overhang"),
        ("S->RepeatX(2, Al)\nAl->O\nO->Overhang(0.2, 0.2, A)\nA->Color(1, 0, 0)\n", "RepeatX cannot hold an Overhang"),
    ],
)
def test_misplaced_or_too_wide_overhangs_are_located(text, message):
    with pytest.raises(GrammarError) as caught:
        loads(text, "o.grammar")
    assert message in str(caught.value) and "o.grammar:" in str(caught.value)
