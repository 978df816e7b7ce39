"""The grammar's randomness: every seed (0 too) moves the facade, and rules draw independent streams."""

from __future__ import annotations

import numpy as np

from cityshade.assets import tile_array
from cityshade.grammar import compile_grammars, evaluate, facade_seed_vector, loads, seed_cells, seed_vector
from cityshade.grammar.testing import facade_cells


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
    text = "S->RepeatX(0.5, Pick)\nPick->RandUni(0, X, Y)\nX->RandUni(0, P0, P1)\nY->RandUni(0, P2, P3)\n" + "".join(
        f"P{i}->Mat(Color, 0, {i / 4:.2f}, 0.5, 0.5, 1)\n" for i in range(4)
    )
    compiled, terminal = _choices(text)
    shares = np.array([np.mean(terminal == compiled.address("g", f"P{i}")) for i in range(4)])
    assert np.all(np.abs(shares - 0.25) < 0.05), shares


def test_seed_zero_varies_a_facade():
    text = "S->RepeatX(0.5, Pick)\nPick->RandUni(0, A, B)\nA->Mat(Color, 0, 1, 0, 0, 1)\nB->Mat(Color, 0, 0, 0, 1, 1)\n"
    pictures = {_choices(text, 200, seed)[1].tobytes() for seed in range(4)}
    assert len(pictures) == 4


def test_facade_cells():
    cells = seed_cells(np.arange(2000))
    assert (facade_cells(cells, 0) == cells).all()  # facade 0 is the building's own seed
    for face in (4, 8, 12):
        hashed = facade_cells(cells, face)
        assert (hashed >= 1).all() and (hashed <= 2047).all()
        assert np.mean(np.all(hashed == cells, axis=1)) < 0.01
    assert facade_seed_vector(7, 0) == seed_vector(7)
    assert facade_seed_vector(7, 4) == facade_seed_vector(7, 4) != facade_seed_vector(7, 8)


def test_the_sides_of_a_building_choose_independently():
    """A random choice per bay: with one seed per building every side would copy the front (all
    choices equal); with a stream per facade about half of them agree (two choices), over buildings."""
    text = "S->RepeatX(1, Pick)\nPick->RandUni(0, A, B)\nA->Color(1, 0, 0)\nB->Color(0, 0, 1)\n"
    compiled = compile_grammars({"g": loads(text)})
    uv = np.stack([np.arange(20, dtype=np.float32) + 0.5, np.full(20, 0.5, np.float32)], axis=1)

    def choices(seed, face):
        return evaluate(
            compiled, compiled.address("g"), uv, (20.0, 1.0), facade_seed_vector(seed, face), tile_array(16)
        ).terminal

    agree = [np.mean(choices(seed, 0) == choices(seed, side)) for seed in range(30) for side in (4, 8, 12)]
    assert 0.4 < np.mean(agree) < 0.6, np.mean(agree)
    assert all((choices(seed, 4) == choices(seed, 4)).all() for seed in range(5))  # the same in every frame


def test_a_choice_with_no_stack_entry_is_made_once_per_building():
    """Rand/RandUni with l >= 1 and no RandStack entry draw from the building's seed (entry 0 of
    the stack): every side of a building makes the same choice, buildings differ."""
    text = "S->RepeatX(1, Pick)\nPick->RandUni(1, A, B)\nA->Color(1, 0, 0)\nB->Color(0, 0, 1)\n"
    compiled = compile_grammars({"g": loads(text)})
    uv = np.stack([np.arange(8, dtype=np.float32) + 0.5, np.full(8, 0.5, np.float32)], axis=1)
    picked = []
    for seed in range(20):
        sides = [
            evaluate(
                compiled,
                compiled.address("g"),
                uv,
                (8.0, 1.0),
                facade_seed_vector(seed, face),
                tile_array(16),
                building_seed=seed_vector(seed),
            ).terminal
            for face in (0, 4, 8, 12)
        ]
        assert all((side == sides[0][0]).all() for side in sides)  # one choice for every bay and side
        picked.append(int(sides[0][0]))
    assert len(set(picked)) == 2  # but not the same for every building
