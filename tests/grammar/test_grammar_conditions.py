"""Case and its conditions: the right branch for every index and size (hypothesis), and bad
conditions refused with FILE:LINE:COL."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cityshade.assets import tile_array
from cityshade.grammar import GrammarError, compile_grammars, evaluate, loads
from cityshade.scene import USES

ARITHMETIC = ["+", "-", "*", "%"]
COMPARISONS = ["==", "!=", "<", "<=", ">", ">="]


def _expressions():
    leaves = st.one_of(st.sampled_from(["split.index", "split.total", "scope.sx"]), st.integers(0, 6).map(str))
    values = st.recursive(
        leaves,
        lambda inner: st.tuples(inner, st.sampled_from(ARITHMETIC), inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        max_leaves=4,
    )
    comparison = st.tuples(values, st.sampled_from(COMPARISONS), values).map(lambda t: f"{t[0]} {t[1]} {t[2]}")
    return st.recursive(
        comparison,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["&&", "||"]), inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
            inner.map(lambda e: f"!({e})"),
        ),
        max_leaves=3,
    )


def expected(text: str, index: float, total: float, sx: float) -> bool:
    """The condition in Python: C's operators, '%' floored and 0 for a zero divisor."""

    def mod(a, b):
        return 0.0 if b == 0 else a - b * math.floor(a / b)

    code = text.replace("&&", " and ").replace("||", " or ").replace("!(", " not (").replace(" not (=", "!=(")
    code = code.replace("split.index", repr(index)).replace("split.total", repr(total)).replace("scope.sx", repr(sx))
    return bool(eval(_floored(code), {"mod": mod}))  # noqa: S307 (test-generated arithmetic only)


def _floored(code: str) -> str:
    """Rewrites every 'a % b' (operands are parenthesised or atoms) into mod(a, b)."""
    while " % " in code:
        at = code.index(" % ")
        start, depth = at - 1, 0
        while True:
            depth += {")": 1, "(": -1}.get(code[start], 0)
            if depth == 0 and (code[start] == "(" or start == 0 or code[start - 1] in " ("):
                break
            start -= 1
        end, depth = at + 3, 0
        while True:
            depth += {"(": 1, ")": -1}.get(code[end], 0)
            if depth == 0 and (end + 1 == len(code) or code[end + 1] in " )"):
                break
            end += 1
        code = code[:start] + f"mod({code[start:at]}, {code[at + 3 : end + 1]})" + code[end + 1 :]
    return code


@settings(max_examples=40, deadline=None)
@given(condition=_expressions(), tile=st.sampled_from([0.75, 1.0, 1.5, 2.5]), width=st.sampled_from([6.0, 9.0, 12.0]))
def test_case_picks_the_branch_python_would(condition, tile, width):
    text = (
        f"S->RepeatX({tile}, Cell)\nCell->Case({condition}, A, B)\n"
        "A->Mat(Color, 0, 1, 0, 0, 1)\nB->Mat(Color, 0, 0, 0, 1, 1)\n"
    )
    try:
        grammar = loads(text)
    except GrammarError as exc:  # a constant zero divisor, or a condition over the GPU's limits, is refused
        assert "by zero" in str(exc) or "the GPU limit is" in str(exc)
        assume(False)
    compiled = compile_grammars({"g": grammar})
    count = max(math.floor(width / tile + 0.5), 1)
    sx = float(np.float32(width) / np.float32(count))
    u = (np.arange(count, dtype=np.float32) + 0.5) * np.float32(sx)
    uv = np.stack([u, np.full_like(u, 0.5)], axis=1)
    result = evaluate(compiled, compiled.address("g"), uv, (width, 1.0), (0.0, 0.0), tile_array(16))
    for i in range(count):
        want = compiled.address("g", "A" if expected(condition, float(i), float(count), sx) else "B")
        assert result.terminal[i] == want, (condition, i, count, sx)


@settings(max_examples=30, deadline=None)
@given(
    use=st.sampled_from(list(USES)),
    asked=st.sampled_from(list(USES)),
    height=st.floats(1, 200, width=32),
    threshold=st.integers(1, 200),
)
def test_use_and_height_pick_the_branch(use, asked, height, threshold):
    """building.use == use.NAME is true exactly for that use; building.height compares as a number."""
    text = (
        f"S->Case(building.use == use.{asked} && building.height > {threshold}, A, "
        f"building.use != use.{asked}, B, C)\n"
        + "".join(f"{n}->Color({v}, 0, 0)\n" for n, v in zip("ABC", (1, 0.5, 0)))
    )
    compiled = compile_grammars({"g": loads(text)})
    result = evaluate(
        compiled,
        compiled.address("g"),
        np.array([[0.5, 0.5]], np.float32),
        (1.0, 1.0),
        (0.0, 0.0),
        tile_array(16),
        building=(3, 0, USES[use], height),
    )
    want = "A" if use == asked and height > threshold else "B" if use != asked else "C"
    assert result.terminal[0] == compiled.address("g", want)


@pytest.mark.parametrize(
    "text, message",
    [
        ("S->Case(split.indx == 0, A, A)\n", "1:9: error: unknown variable 'split.indx' in a condition"),
        ("S->Case(levels > 3, A, A)\n", "1:9: error: unknown variable 'levels' in a condition"),
        ("S->Case(building.usage == 2, A, A)\n", "1:9: error: unknown variable 'building.usage' in a condition"),
        ("S->Case(building.use == use.ofice, A, A)\n", "1:25: error: unknown use 'use.ofice'"),
        ("S->Case(building.use == use.zzz, A, A)\n", "uses: use.mixed, use.home, use.office, use.shop"),
        ("S->Case(split.index % (2 - 2) == 0, A, A)\n", "1:21: error: '%' by zero"),
        ("S->Case(scope.sx / 0 > 1, A, A)\n", "1:18: error: '/' by zero"),
        ("S->Case(split.first, A)\n", "Case takes ((condition, rule)..., rule) but got 2 arguments"),
        ("S->Case(split.first, 1 + 2, A)\n", "1:22: error: Case expects a rule name here"),
        ("S->Case(" + " + ".join(["split.index"] * 20) + " > 0, A, A)\n", "take 42 steps; the GPU limit is 32"),
        ("S->RepeatX(rand(2), A)\n", "1:12: error: rand takes two numbers"),
        ("S->RepeatX(rand(3, 2), A)\n", "1:12: error: rand(3, 2) needs 0 < low <= high"),
        ("S->RepeatX(rnd(2, 3), A)\n", "1:12: error: unknown function 'rnd'"),
        ("S->Intrusion(rand(1, 2), A, A, A, A, A)\n", "Intrusion takes a fixed size"),
        ("S->SplitX(Tile, rand(1, 2), A)\n", "1:17: error: a Tile's size is fixed"),
        ("S->Layer(F(1, 2))\nF(i)->Case(i > 0, A, A)\n", "1:10: error: rule 'F' takes 1 argument, got 2"),
        ("S->Layer(F)\nF(i)->Case(i > 0, A, A)\n", "1:10: error: rule 'F' takes 1 parameter (i)"),
        ("S->Layer(F(2))\nF(i)->Case(j > 0, A, A)\n", "2:12: error: unknown variable 'j' in a condition"),
        ("S->Layer(F(1, 2, 3, 4, 5))\nF(a, b, c, d, e)->Case(a > 0, A, A)\n", "has 5 parameters; the GPU limit is 4"),
        ("S->F(split.index / 0)\nF(i)->Case(i > 0, A, A)\n", "1:18: error: '/' by zero"),
        ("S->Color(0.2, 0.3, 0.4, windw)\n", "1:25: error: Color expects a label here, not 'windw'"),
        ("S->Color(0.2, 1.3, 0.4)\n", "1:15: error: a colour channel is in [0, 1], got 1.3"),
        ("S->SplitX(Tile, 1, A, Rel, 1, A, Tile, 2, A)\n", "1:34: error: a Split has at most one Tile part"),
    ],
)
def test_bad_conditions_are_located(text, message):
    with pytest.raises(GrammarError) as info:
        loads(text + "A->Mat(Color, 0, 1, 0, 0, 1)\n", "bad.grammar")
    assert message in str(info.value)


def test_an_index_no_split_can_reach_is_refused():
    text = (
        "S->SplitY(Rel, 1, Row, Rel, 1, Row, Rel, 1, Row)\nRow->Layer(Pick)\n"
        "Pick->Case(split.index == 1, A, 3 == split.index, A, A)\nA->Mat(Color, 0, 1, 0, 0, 1)\n"
    )
    with pytest.raises(GrammarError) as info:
        loads(text, "bad.grammar")
    message = str(info.value)
    assert "bad.grammar:3:35: error: split.index is never 3 here: it runs from 0 to 2" in message
    assert "3:23" not in message  # index 1 exists
    loads(text.replace("S->SplitY(", "S->SplitY(Tile, 2, Row, "))  # a Tile: the total is only known at run time
