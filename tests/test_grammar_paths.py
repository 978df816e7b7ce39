"""The forward (depth prepass) and deferred (G-buffer + full-screen) facade paths draw the same city."""

from __future__ import annotations

import numpy as np
from PIL import Image

from cityshade.assets import tile_array
from cityshade.bench.facades import city_masses, views
from cityshade.grammar import compile_grammars, library_path, load
from cityshade.gl import linear_to_srgb
from cityshade.grammar._city_render import PATHS, FacadeCityRenderer
from cityshade.scene import Camera
from render_checks import render_finite


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


def test_city_frame_paths_agree(gl_context, output_dir):
    """The city's frame with grammar facades deferred (the default) or forward looks the same."""
    from cityshade.render import Renderer, RenderSettings
    from cityshade.scene import City, box

    masses = [box((0.0, 0.0), 20.0, 14.0, 19.0, seed=5, style=6), box((26.0, 0.0), 14.0, 14.0, 25.0, seed=6, style=3)]
    camera = Camera((14.0, 5.0, -22.0), (18.0, 9.0, 7.0), fov_y=60.0)
    images = {}
    for deferred in (False, True):
        renderer = Renderer((128, 96), RenderSettings(lights=0.7, grammar_deferred=deferred), ctx=gl_context)
        renderer.set_city(City("paths", 0, masses, [], (-40.0, -40.0, 60.0, 60.0)))
        images[deferred] = render_finite(renderer, camera).astype(np.int16)
        Image.fromarray(images[deferred].astype(np.uint8)).save(output_dir / f"grammar_city_deferred_{deferred}.png")
        renderer.release()
    differ = np.abs(images[True] - images[False]).max(axis=-1) > 24
    assert differ.mean() < 0.02, f"{differ.sum()} pixels differ"


def test_ssao_only_darkens_and_at_most_by_its_strength(gl_context, output_dir):
    """SSAO on (the output) against off (the lit colour before the pass, sRGB-encoded as the pass
    does, exactly): the sky is untouched, no pixel gets brighter, none darker than 1 - 0.6 of its light,
    and some pixels are darkened."""
    masses, side = city_masses(16)
    compiled = compile_grammars({"dusk": load(library_path("dusk.grammar"))})
    renderer = FacadeCityRenderer(gl_context, masses, compiled, tile_array(32), (128, 96))
    renderer.set_grammar(compiled.address("dusk"))
    renderer.draw(views(side)["street"], "deferred")
    on = renderer.read().astype(float) / 255
    lit = np.clip(renderer.lit.read(0)[..., :3].astype(float), 0, 1)
    width, height = renderer.size
    sky = np.frombuffer(renderer.gbuffer.depth.read(), np.float32).reshape(height, width)[::-1] >= 1.0
    renderer.release()
    off = linear_to_srgb(lit).astype(float)
    Image.fromarray((np.hstack([off, on]) * 255).round().astype(np.uint8)).save(output_dir / "grammar_ssao_off_on.png")
    step = 1.5 / 255  # 8-bit rounding and half-float input
    assert sky.any() and np.abs(on - off)[sky].max() <= step, "the sky is untouched"
    assert (on <= off + step).all(), "SSAO never brightens"
    assert (on >= linear_to_srgb(0.4 * lit) - step).all(), "SSAO darkens by at most 60%"
    darkened = (off - on).max(axis=-1) > 4 / 255
    print(f"SSAO darkens {darkened.mean():.1%} of the pixels")
    assert 0.01 < darkened.mean() < 0.9
