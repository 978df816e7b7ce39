"""The grammar's randomness: every seed (0 too) moves the facade, and rules draw independent streams."""

from __future__ import annotations

import numpy as np

from cityshade.assets import tile_array
from cityshade.grammar import compile_grammars, loads
from cityshade.grammar._random import seed_cells, seed_vector
from cityshade.grammar._reference import evaluate


def test_seed_zero_is_a_seed_like_any_other():
    cells = seed_cells(np.arange(10_000))
    assert (cells > 0).all() and (cells < 2048).all()
    assert seed_vector(0) != (0.0, 0.0)
    assert len({tuple(c) for c in cells}) > 9_900  # distinct facades, almost never a collision


def _choices(text: str, cells: int = 2000, seed: int = 0):
    compiled = compile_grammars({"g": loads(text)})
    u = (np.arange(cells, dtype=np.float32) + 0.5) * 0.5
    uv = np.stack([u, np.full_like(u, 0.25)], axis=1)
    result = evaluate(compiled, compiled.address("g"), uv, (cells * 0.5, 0.5), seed_vector(seed), tile_array(16))
    return compiled, result.terminal


def test_choices_at_the_same_corner_are_independent():
    """An outer and an inner RandUni decide at the same corner; with one stream the inner choice
    would copy the outer one (X always P0, Y always P3)."""
    text = ("S->RepeatX(0.5, Pick)\nPick->RandUni(0, X, Y)\nX->RandUni(0, P0, P1)\nY->RandUni(0, P2, P3)\n"
            + "".join(f"P{i}->Mat(Color, 0, {i / 4:.2f}, 0.5, 0.5, 1)\n" for i in range(4)))
    compiled, terminal = _choices(text)
    shares = np.array([np.mean(terminal == compiled.address("g", f"P{i}")) for i in range(4)])
    assert np.all(np.abs(shares - 0.25) < 0.05), shares


def test_seed_zero_varies_a_facade():
    text = "S->RepeatX(0.5, Pick)\nPick->RandUni(0, A, B)\nA->Mat(Color, 0, 1, 0, 0, 1)\nB->Mat(Color, 0, 0, 0, 1, 1)\n"
    pictures = {_choices(text, 200, seed)[1].tobytes() for seed in range(4)}
    assert len(pictures) == 4
