"""Properties of the reference evaluator: Split follows eq. 1, Repeat's element size, RandUni's spread."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cityshade.assets import tile_array
from cityshade.grammar import compile_grammars, evaluate, loads

SAMPLES = 4000


def stored(value: float) -> float:
    """A size as the grammar texture stores it (16-bit float)."""
    return float(np.float16(value))


def colours(count: int) -> str:
    return "".join(f"P{i}->Mat(Color, 0, {i / count:.4f}, 0.5, 0.5, 1)\n" for i in range(count))


def run_along_x(text: str, width: float):
    compiled = compile_grammars({"g": loads(text)})
    u = (np.arange(SAMPLES, dtype=np.float32) + 0.5) / SAMPLES * width
    uv = np.stack([u, np.full_like(u, 0.5)], axis=1)
    result = evaluate(compiled, compiled.address("g"), uv, (width, 1.0), (0.0, 0.0), tile_array(16))
    return compiled, result.terminal


parts = st.lists(st.tuples(st.sampled_from(["Abs", "Rel"]), st.floats(0.5, 4.0)), min_size=1, max_size=6)


@settings(max_examples=25, deadline=None)
@given(parts=parts, slack=st.floats(1.0, 20.0))
def test_split_widths_follow_equation_1(parts, slack):
    parts = [(p, stored(v)) for p, v in parts]
    absolute = sum(v for p, v in parts if p == "Abs")
    relative = sum(v for p, v in parts if p == "Rel")
    width = absolute + slack
    text = "S->SplitX(" + ", ".join(f"{p}, {v!r}, P{i}" for i, (p, v) in enumerate(parts)) + ")\n"
    compiled, terminal = run_along_x(text + colours(len(parts)), width)
    scale = (width - absolute) / relative if relative else 0.0
    step = width / SAMPLES
    for i, (policy, value) in enumerate(parts):
        expected = value if policy == "Abs" else value * scale
        if i == len(parts) - 1 and not relative:
            expected = width - sum(v for _, v in parts[:-1])  # the last part takes what is left
        measured = np.count_nonzero(terminal == compiled.address("g", f"P{i}")) * step
        assert abs(measured - expected) <= 2 * step + 0.002 * expected


@settings(max_examples=25, deadline=None)
@given(size=st.floats(0.5, 5.0), width=st.floats(1.0, 40.0), rounding=st.sampled_from(["", ", Nearest", ", Ceil"]))
def test_repeat_element_size(size, width, rounding):
    text = "S->RepeatX(%.3f, Cell%s)\nCell->SplitX(Rel, 1, P0, Rel, 1, P1)\n" % (size, rounding) + colours(2)
    compiled, terminal = run_along_x(text, width)
    ratio = np.float32(width) / np.float32(stored(round(size, 3)))
    if rounding == ", Ceil":
        count = max(np.ceil(ratio - np.float32(1e-4)), 1)  # the paper: S_w / ceil(S_w / v)
    else:
        count = max(np.floor(ratio + np.float32(0.5)), 1)  # CGA: the nearest whole number of tiles
    changes = np.count_nonzero(np.diff(terminal) != 0) + 1
    assert changes == 2 * count  # every element split in two halves


@pytest.mark.parametrize("width, nearest, ceil", [(30.0, 7, 8), (29.0, 7, 7), (31.6, 8, 8), (1.0, 1, 1)])
def test_repeat_counts_by_hand(width, nearest, ceil):
    """A 4.2 m window bay on a 30 m facade: 7 bays (7.14 rounds to 7), where ceil gave 8."""
    for rounding, expected in (("", nearest), (", Ceil", ceil)):
        text = f"S->RepeatX(4.2, Cell{rounding})\nCell->SplitX(Rel, 1, P0, Rel, 1, P1)\n" + colours(2)
        _, terminal = run_along_x(text, width)
        assert np.count_nonzero(np.diff(terminal) != 0) + 1 == 2 * expected


floating = st.lists(st.tuples(st.sampled_from(["Abs", "Rel"]), st.floats(0.5, 3.0)), min_size=0, max_size=4)


@settings(max_examples=30, deadline=None)
@given(before=floating, after=floating, tile=st.floats(0.8, 4.0), slack=st.floats(0.0, 30.0))
@example(before=[], after=[("Abs", 1.0), ("Abs", 1.6882), ("Rel", 2.4004)], tile=1.127, slack=14.859375)  # 11.5 tiles
def test_floating_parts_and_tiles_fill_the_scope(before, after, tile, slack):
    """Relative parts and the Tile's copies float with one scale and fill what the absolute parts
    leave; the tile count is CGA's nearest count of the space left for it, at least 1."""
    before = [(p, stored(v)) for p, v in before]
    after = [(p, stored(v)) for p, v in after]
    tile = stored(tile)
    parts = before + [("Tile", tile)] + after
    absolute = sum(v for p, v in parts if p == "Abs")
    relative = sum(v for p, v in parts if p == "Rel")
    width = absolute + slack + 0.5
    text = "S->SplitX(" + ", ".join(f"{p}, {v!r}, P{i}" for i, (p, v) in enumerate(parts)) + ")\n"
    compiled, terminal = run_along_x(text + colours(len(parts)), width)
    # The texture stores the sums of the parts as 16-bit floats too, so where the space left lies
    # within their rounding of half a tile, the count may round either way: the parts must fit one.
    counts = sorted(
        {nearest_count(width - a - r, tile) for a, r in ((absolute, relative), (stored(absolute), stored(relative)))}
    )
    misfits = [misfit(compiled, terminal, parts, width, absolute, relative, tile, count) for count in counts]
    assert min(misfits, key=len) == [], misfits
    tile_runs = np.count_nonzero(np.diff((terminal == compiled.address("g", f"P{len(before)}")).astype(int)) == 1)
    starts_with_tile = not before
    assert tile_runs + starts_with_tile == 1  # the copies of one rule lie side by side


def nearest_count(space: float, tile: float) -> float:
    """CGA's nearest whole number of tiles in float32, as the evaluator counts them, at least 1."""
    return max(np.floor(np.float32(space) / np.float32(tile) + np.float32(0.5)), 1)


def misfit(compiled, terminal, parts, width, absolute, relative, tile, count) -> list[str]:
    """The parts whose measured widths differ from those `count` tiles give, and whether they fill the scope."""
    scale = (width - absolute) / (relative + count * tile)
    step = width / SAMPLES
    found, total = [], 0.0
    for i, (policy, value) in enumerate(parts):
        expected = value if policy == "Abs" else value * scale * (count if policy == "Tile" else 1)
        measured = np.count_nonzero(terminal == compiled.address("g", f"P{i}")) * step
        total += measured
        if abs(measured - expected) > 2 * step + 0.002 * expected:
            found.append(f"{count:.0f} tiles: part {i} measures {measured:.3f}, expected {expected:.3f}")
    if abs(total - width) > step:  # the parts fill the scope, nothing left, nothing over
        found.append(f"{count:.0f} tiles: the parts measure {total:.3f} of {width:.3f}")
    return found


def test_tile_copies_are_separate_scopes():
    text = "S->SplitX(Abs, 1.0, P0, Tile, 2.0, Cell, Rel, 1.0, P1)\nCell->SplitX(Rel, 1, P2, Rel, 1, P3)\n" + colours(4)
    compiled, terminal = run_along_x(text, 12.0)  # (12 - 1 - 1) / 2 = 5 tiles of 2 m, scale 1
    halves = np.count_nonzero(np.diff(terminal) != 0) + 1 - 2
    assert halves == 2 * 5


def test_rand_uni_spreads_evenly():
    text = "S->RepeatX(0.5, R)\nR->RandUni(0, P0, P1, P2, P3)\n" + colours(4)
    compiled, terminal = run_along_x(text, 400.0)
    cells = terminal[:: SAMPLES // 800]  # one sample per element
    counts = np.array([np.count_nonzero(cells == compiled.address("g", f"P{i}")) for i in range(4)])
    assert counts.min() > 0.15 * len(cells)


@settings(max_examples=20, deadline=None)
@given(low=st.floats(0.5, 3.0), spread=st.floats(0.0, 3.0), seed=st.integers(0, 2**31 - 1))
def test_rand_sizes_stay_in_range_fill_the_scope_and_are_stable(low, spread, seed):
    """An absolute rand(low, high) part: its width lies in [low, high], the floating part takes
    the rest, and the same facade and seed draw the same width."""
    from cityshade.grammar import seed_vector

    low, high = stored(low), stored(low + spread)
    text = f"S->SplitX(Abs, rand({low!r}, {high!r}), P0, Rel, 1, P1)\n" + colours(2)
    compiled = compile_grammars({"g": loads(text)})
    width = high + 2.0
    u = (np.arange(SAMPLES, dtype=np.float32) + 0.5) / SAMPLES * width
    uv = np.stack([u, np.full_like(u, 0.5)], axis=1)
    runs = [
        evaluate(compiled, compiled.address("g"), uv, (width, 1.0), seed_vector(seed), tile_array(16)).terminal
        for _ in range(2)
    ]
    assert np.array_equal(runs[0], runs[1])
    step = width / SAMPLES
    drawn = np.count_nonzero(runs[0] == compiled.address("g", "P0")) * step
    assert low - 2 * step <= drawn <= high + 2 * step
    assert np.count_nonzero(runs[0] == compiled.address("g", "P1")) * step == pytest.approx(width - drawn, abs=2 * step)


def test_rand_sizes_vary_with_the_seed():
    from cityshade.grammar import seed_vector

    text = "S->SplitX(Abs, rand(1, 5), P0, Rel, 1, P1)\n" + colours(2)
    compiled = compile_grammars({"g": loads(text)})
    u = (np.arange(SAMPLES, dtype=np.float32) + 0.5) / SAMPLES * 8
    uv = np.stack([u, np.full_like(u, 0.5)], axis=1)
    widths = {
        np.count_nonzero(
            evaluate(compiled, compiled.address("g"), uv, (8.0, 1.0), seed_vector(s), tile_array(16)).terminal
            == compiled.address("g", "P0")
        )
        for s in range(6)
    }
    assert len(widths) >= 4


@settings(max_examples=20, deadline=None)
@given(tile=st.sampled_from([0.75, 1.0, 1.5]), k=st.integers(1, 4), offset=st.integers(-3, 3))
def test_parameters_carry_each_elements_value(tile, k, offset):
    """Cell(split.index + offset) passes each element's own value: Case picks by it."""
    text = f"S->RepeatX({tile}, Cell(split.index + {offset}))\nCell(i)->Case(i % {k} == 0, P0, P1)\n" + colours(2)
    compiled, terminal = run_along_x(text, 9.0)
    count = max(int(np.floor(9.0 / tile + 0.5)), 1)
    centres = ((np.arange(count) + 0.5) * (9.0 / count) / 9.0 * SAMPLES).astype(int)
    want = [compiled.address("g", "P0" if (i + offset) % k == 0 else "P1") for i in range(count)]
    assert terminal[centres].tolist() == want
