"""The style library: every style checks, compiles small, and renders the same on GPU and numpy."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.assets import LABELS, tile_array
from cityshade.grammar import LIBRARY_STYLES, compile_grammars, evaluate_facade, load_library, seed_vector
from grammar_compare import compare, ctx  # noqa: F401  (ctx is a fixture)


@pytest.fixture(scope="module")
def library():
    grammars = load_library()
    return grammars, compile_grammars(grammars)


def test_library_has_six_styles_in_one_small_texture(library):
    grammars, compiled = library
    assert len(LIBRARY_STYLES) >= 6
    rules = sum(len(g.rules) for g in grammars.values())
    assert compiled.nbytes / rules <= 16  # paper §6: 18 bytes per rule
    assert compiled.used < 2048


@pytest.mark.parametrize("style", LIBRARY_STYLES)
def test_style_gpu_matches_numpy(ctx, library, style, output_dir):  # noqa: F811 (fixture)
    _, compiled = library
    compare(ctx, compiled, style, output_dir, seed=7, facade=(20.0, 16.0), size=(120, 96), min_terminals=3)


# the filtered (mipmapped) path with every pixel's ids equal to the twin's
EXACT = dict(seed=7, size=(120, 96), min_terminals=3, nearest=False, allowed=0)


@pytest.mark.parametrize("style", LIBRARY_STYLES)
def test_filtered_colour_keeps_exact_labels(ctx, library, style, output_dir):  # noqa: F811 (fixture)
    """The mipmapped path: the terminal, label and glass flag come from the nearest texels, equal
    to the numpy twin's on every pixel, while the colour is filtered."""
    _, compiled = library
    compare(ctx, compiled, style, output_dir, facade=(40.0, 32.0), **EXACT)


@pytest.mark.parametrize("nearest", [True, False])
def test_the_benchmarks_conditions_facade_matches_numpy(ctx, nearest, output_dir):  # noqa: F811 (fixture)
    from cityshade.grammar import library_path, load

    compiled = compile_grammars({"conditions": load(library_path("conditions.grammar"))})
    cpu, _ = compare(
        ctx, compiled, "conditions", output_dir, facade=(20.0, 16.0), size=(120, 96), nearest=nearest, allowed=0
    )
    assert len(np.unique(cpu.terminal)) >= 4  # wall and the three windows


GROUND_FLOORS = {"brick": "door", "classical": "door", "office": "door", "shops": "shop", "storeys": "shop"}


@pytest.mark.parametrize("style", GROUND_FLOORS)
def test_ground_floor_only_on_faces_starting_at_the_ground(ctx, library, style, output_dir):  # noqa: F811
    """A face at facade.level 0 has the style's ground floor (its doors or shop fronts); a face two
    storeys up (a dome's third ring, a part raised off the ground) has none, but the storeys above
    it, from its bottom up. GPU and numpy alike, labels exactly (filtered path)."""
    _, compiled = library
    label = LABELS.index(GROUND_FLOORS[style])
    shown = {}
    for level in (0, 2):
        cpu, _ = compare(ctx, compiled, style, output_dir, facade=(20.0, 16.0), level=level, **EXACT)
        shown[level] = int(np.count_nonzero(cpu.label == label))
        if level:
            assert {LABELS[i] for i in np.unique(cpu.label[-6:])} & {"window", "room", "balcony"}, (
                "storeys from the bottom"
            )
    print(f"{style}: {shown[0]} {GROUND_FLOORS[style]} pixels at level 0, {shown[2]} at level 2")
    assert shown[0] > 100 and shown[2] == 0


def test_dusk_shows_rooms_through_holes(library):
    _, compiled = library
    cpu = evaluate_facade(compiled, compiled.address("dusk"), (20.0, 16.0), (120, 96), seed_vector(2), tile_array(32))
    labels = {LABELS[i] for i in np.unique(cpu.label)}
    assert {"wall", "window", "room"} <= labels


def test_seeds_vary_a_style(library):
    _, compiled = library
    images = [
        evaluate_facade(
            compiled, compiled.address("brick"), (20.0, 16.0), (60, 48), seed_vector(s), tile_array(32)
        ).terminal
        for s in range(4)
    ]
    assert len({im.tobytes() for im in images}) > 1


def test_fig12_keeps_the_papers_ceil_rounding():
    """fig12.grammar writes `Ceil`: a 21 m facade has ceil(21 / 2.5) = 9 windows on its ground
    floor, as in the paper, where the nearest count would give 8."""
    from cityshade.grammar import evaluate, library_path, load

    compiled = compile_grammars({"f": load(library_path("fig12.grammar"))})
    u = (np.arange(2100, dtype=np.float32) + 0.5) / 100
    uv = np.stack([u, np.full_like(u, 1.5)], axis=1)  # through the ground floor's windows
    result = evaluate(compiled, compiled.address("f"), uv, (21.0, 13.7), seed_vector(1), tile_array(32))
    window = result.label == LABELS.index("window")
    assert np.count_nonzero(np.diff(window.astype(int)) == 1) + window[0] == 9
