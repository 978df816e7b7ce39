"""The forward (depth prepass) and deferred (G-buffer + full-screen) facade paths draw the same city."""

from __future__ import annotations

import numpy as np
from PIL import Image

from cityshade.assets import tile_array
from cityshade.bench.facades import city_masses, views
from cityshade.grammar import compile_grammars, library_path, load
from cityshade.grammar._city_render import PATHS, FacadeCityRenderer


def test_forward_and_deferred_agree(gl_context, output_dir):
    masses, side = city_masses(16)
    compiled = compile_grammars({"dusk": load(library_path("dusk.grammar"))})
    renderer = FacadeCityRenderer(gl_context, masses, compiled, tile_array(32), (128, 96))
    renderer.set_grammar(compiled.address("dusk"))
    images = {}
    for path in PATHS:
        renderer.draw(views(side)["street"], path)
        images[path] = renderer.read().astype(np.int16)
        Image.fromarray(images[path].astype(np.uint8)).save(output_dir / f"grammar_path_{path}.png")
    renderer.release()
    differ = np.abs(images["forward"] - images["deferred"]).max(axis=-1) > 24
    # texture filtering footprints differ slightly (screen derivatives vs neighbouring texels)
    assert differ.mean() < 0.02, f"{differ.sum()} pixels differ"
    assert images["forward"].std() > 10  # not an empty picture
