"""The forward (depth prepass) and deferred (G-buffer + full-screen) facade paths draw the same city,
and the frame's SSAO pass only darkens."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.bench.facades import fig11_city, fig11_settings, views
from cityshade.errors import UsageError
from cityshade.grammar import library_texture, library_texture_with
from cityshade.render import Renderer, frame_passes
from cityshade.scene import Camera
from render_checks import render_finite

SIZE = (128, 96)


@pytest.fixture(scope="module")
def fig11(gl_context):
    """The benchmark's grid city of 16 buildings, all with the dusk grammar, and its street camera."""
    city, side = fig11_city(16)
    renderer = Renderer(SIZE, fig11_settings("deferred", "full"), ctx=gl_context)
    renderer.set_city(city)
    yield renderer, views(side)["street"]
    renderer.release()


@pytest.mark.slow  # test_city_frame_paths_agree checks the same in a city (make test-slow)
def test_forward_and_deferred_agree(fig11, output_dir):
    renderer, camera = fig11
    images = {}
    for path in ("forward", "deferred"):
        renderer.set_settings(fig11_settings(path, "full"))
        images[path] = render_finite(renderer, camera).astype(np.int16)
        Image.fromarray(images[path].astype(np.uint8)).save(output_dir / f"grammar_path_{path}.png")
    differ = np.abs(images["forward"] - images["deferred"]).max(axis=-1) > 24
    # texture filtering footprints differ slightly (screen derivatives vs neighbouring texels)
    assert differ.mean() < 0.02, f"{differ.sum()} pixels differ"
    assert images["forward"].std() > 10  # not an empty picture


def test_grammar_start_and_files_switch_the_facades(fig11):
    """grammar_start draws every grammar facade with one grammar (here one compiled from
    grammar_files, after the library, whose addresses stay put); an unknown name is refused."""
    renderer, camera = fig11
    extra = library_texture_with(renderer.settings.grammar_files)
    assert {k: v for k, v in extra.addresses.items() if k[0] in library_texture().starts} == library_texture().addresses
    pictures = {}
    for grammar in ("simple", "full"):
        renderer.set_settings(fig11_settings("deferred", grammar))
        pictures[grammar] = render_finite(renderer, camera).astype(np.int16)
    changed = np.abs(pictures["simple"] - pictures["full"]).max(axis=-1) > 24
    assert changed.mean() > 0.1, f"only {changed.sum()} pixels changed"
    renderer.set_settings(renderer.settings.with_(grammar_start="no such grammar"))
    with pytest.raises(UsageError, match="unknown grammar_start"):
        renderer.render(camera)
    renderer.set_settings(fig11_settings("deferred", "full"))


def test_ssao_is_a_pass_of_the_frame():
    names = [p.name for p in frame_passes(fig11_settings("deferred", "full"))]
    assert names[names.index("resolve") + 1 :] == ["ssao", "tone map"]
    assert "ssao" not in [p.name for p in frame_passes(fig11_settings("deferred", "full").with_(ssao=False))]


def test_ssao_only_darkens_and_at_most_by_its_strength(fig11, output_dir):
    """SSAO's output (the `occluded` target) against its input (`resolved`), both linear HDR: the
    sky is untouched, no pixel gets brighter, none darker than 1 - 0.6 of its light, and some
    pixels are darkened."""
    renderer, camera = fig11
    renderer.set_settings(fig11_settings("deferred", "full"))
    renderer.render(camera)
    lit = renderer.targets["resolved"].read(0)[..., :3].astype(float)
    on = renderer.targets["occluded"].read(0)[..., :3].astype(float)
    width, height = SIZE
    sky = np.frombuffer(renderer.targets["resolved"].depth.read(), np.float32).reshape(height, width)[::-1] >= 1.0
    tone = np.hstack([lit, on]) / max(lit.max(), 1e-6)
    Image.fromarray((np.clip(tone, 0, 1) ** (1 / 2.2) * 255).round().astype(np.uint8)).save(
        output_dir / "grammar_ssao_off_on.png"
    )
    step = 2e-3 * np.maximum(lit, 1.0)  # half-float rounding of the output
    assert sky.any() and (on[sky] == lit[sky]).all(), "the sky is untouched"
    assert (on <= lit + step).all(), "SSAO never brightens"
    assert (on >= 0.4 * lit - step).all(), "SSAO darkens by at most 60%"
    darkened = (lit - on).max(axis=-1) > 0.02 * lit.max(axis=-1)
    print(f"SSAO darkens {darkened.mean():.1%} of the pixels")
    assert 0.01 < darkened.mean() < 0.9


def test_city_frame_paths_agree(gl_context, output_dir):
    """The city's frame with grammar facades deferred (the default) or forward looks the same."""
    from cityshade.render import RenderSettings
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
