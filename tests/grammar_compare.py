"""Shared by the grammar GPU tests: a GL context and the GPU-vs-numpy comparison of one facade."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.assets import tile_array
from cityshade.grammar import FacadeRenderer, GrammarTextures, evaluate_facade, facade_seed_vector, seed_vector
from render_checks import assert_finite

SIZE = (128, 96)
FACADE = (16.0, 12.0)


@pytest.fixture(scope="module")
def ctx(gl_context):
    # the session's context: objects of one context used while another is current would be wrong
    return gl_context


def compare(
    ctx,
    compiled,
    name,
    output_dir,
    seed=3,
    facade=FACADE,
    size=SIZE,
    min_terminals=2,
    nearest=True,
    allowed=0.001,
    building=(0, 0, 0, 0),
    face=0,
    level=0,
):
    """GPU ids against the numpy twin's; `allowed` is the share of pixels that may differ.
    With nearest=False the GPU filters colours (mipmaps) and ids must still be exact. `face`: which
    facade of the building (the GPU hashes the seed with it, the twin gets facade_seed_vector);
    `level`: facade.level."""
    tiles = tile_array(32)
    textures = GrammarTextures(ctx, compiled, tiles)
    start = compiled.address(name)
    colour, ids = FacadeRenderer(ctx, textures, nearest=nearest).render(
        start, facade, size, seed_vector(seed), building, face, level
    )
    textures.release()
    cpu = evaluate_facade(
        compiled, start, facade, size, facade_seed_vector(seed, face), tiles, building, seed_vector(seed), level
    )
    assert_finite(colour, f"grammar {name} colour")
    suffix = f"_level{level}" if level else ""
    Image.fromarray((np.clip(colour[..., :3], 0, 1) * 255).astype(np.uint8)).save(
        output_dir / f"grammar_{name}{suffix}.png"
    )
    terminal_diff = ids[..., 0].astype(np.int64) - 1 != cpu.terminal
    label_diff = ids[..., 1] != cpu.label
    glass_diff = ids[..., 3].astype(bool) != cpu.glass
    differing = int(np.count_nonzero(terminal_diff | label_diff | glass_diff))
    total = size[0] * size[1]
    mode = "nearest" if nearest else "filtered"
    print(f"{name}{suffix} ({mode}): {differing} of {total} pixels differ ({100 * differing / total:.3f}%)")
    assert differing <= allowed * total, f"{name}: {differing} pixels differ"
    assert len(np.unique(cpu.terminal)) >= min_terminals, "the operator was not exercised"
    return cpu, ids
