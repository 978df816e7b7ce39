"""Dynamic resolution: the scale that keeps a target frame rate (converges, stays within its
bounds, does not hunt) and the bilinear stretch to the window, GPU against its numpy twin."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.errors import UsageError
from cityshade.gl import ProgramCache, RenderTarget
from cityshade.render import ResolutionScale, upscale, upscale_reference


def _run(scaler: ResolutionScale, cost, frames: int, noise: float = 0.0, seed: int = 0) -> list[float]:
    """Scales chosen over `frames` frames whose seconds are cost(scale), times a random factor."""
    rng = np.random.default_rng(seed)
    scales = []
    for _ in range(frames):
        scaler.update(cost(scaler.scale) * (1 + noise * rng.uniform(-1, 1)))
        scales.append(scaler.scale)
    return scales


def _cost(fixed: float, full: float):
    """Seconds per frame: a fixed part plus a part per pixel (`full` at scale 1)."""
    return lambda scale: fixed + full * scale * scale


@pytest.mark.parametrize("fixed, full", [(0.01, 0.3), (0.02, 0.12), (0.0, 1.0), (0.03, 0.06)])
def test_the_scale_converges_to_the_target_rate_and_stays(fixed, full):
    scaler = ResolutionScale(15.0)
    cost = _cost(fixed, full)
    scales = _run(scaler, cost, 90)
    assert len(set(scales[-30:])) == 1, "settled: no change over the last 30 frames"
    fps = 1 / cost(scales[-1])
    at_minimum = scales[-1] == scaler.minimum and fps < 15.0
    at_full = scales[-1] == 1.0 and fps > 15.0
    assert at_minimum or at_full or 15.0 <= fps <= 15.0 * (1 + scaler.band), (scales[-1], fps)


def test_the_scale_stays_between_the_minimum_and_one():
    slow = ResolutionScale(30.0, minimum=0.3)
    assert min(_run(slow, _cost(0.5, 5.0), 60)) == pytest.approx(0.3, abs=1 / 32)
    assert slow.scale >= 0.3 and slow.size((1024, 768)) == (round(1024 * slow.scale), round(768 * slow.scale))
    fast = ResolutionScale(10.0, scale=0.25)
    assert _run(fast, _cost(0.001, 0.01), 60)[-1] == 1.0
    assert max(_run(fast, _cost(0.001, 0.01), 30)) == 1.0


def test_noise_within_the_band_does_not_change_the_scale():
    scaler = ResolutionScale(15.0, scale=0.5)
    # 17 fps at scale 0.5, noise of 5%: inside [target, target * (1 + band)]
    scales = _run(scaler, lambda s: 1 / 17.0 * (s / 0.5) ** 2, 120, noise=0.05, seed=3)
    assert set(scales) == {0.5}


def test_scaling_up_and_down_has_a_gap_between():
    """Just below the target scales down; just above it stays; well above (past the band) scales up."""
    for fps, moves in ((14.0, "down"), (16.0, "stays"), (22.0, "up")):
        scaler = ResolutionScale(15.0, scale=0.5)
        for _ in range(scaler.settle):
            scaler.update(1 / fps)
        assert {"down": scaler.scale < 0.5, "stays": scaler.scale == 0.5, "up": scaler.scale > 0.5}[moves], (
            fps,
            scaler.scale,
        )


@pytest.mark.parametrize(
    "bad",
    [
        dict(target_fps=0.0),
        dict(target_fps=-5.0),
        dict(target_fps=float("nan")),
        dict(target_fps=15.0, minimum=0.0),
        dict(target_fps=15.0, minimum=1.5),
    ],
)
def test_bad_rates_and_minimums_are_refused(bad):
    with pytest.raises(UsageError):
        ResolutionScale(**bad)


@pytest.mark.parametrize("source, window", [((40, 30), (97, 71)), ((64, 48), (64, 48)), ((33, 20), (160, 96))])
def test_the_gpu_stretch_equals_its_numpy_twin(gl_context, source, window):
    rng = np.random.default_rng(source[0])
    image = rng.integers(0, 256, (source[1], source[0], 4), dtype=np.uint8)
    image[..., :2] = np.linspace(0, 255, source[0] * source[1]).reshape(source[1], source[0], 1).astype(np.uint8)
    frame = gl_context.texture(source, 4, image[::-1].tobytes())  # the texture's first row is the image's bottom
    target = RenderTarget(gl_context, window, (("f1", 4),))
    try:
        upscale(ProgramCache(gl_context), frame, target.fbo)
        drawn = target.read()
    finally:
        target.release()
        frame.release()
    expected = upscale_reference(image, window)
    differing = int(np.any(np.abs(drawn.astype(int) - expected) > 1, axis=-1).sum())
    assert drawn.shape == expected.shape and differing == 0, f"{differing} pixels differ by more than 1"


def test_shadow_maps_scale_with_the_frame():
    """Texels per cascade side follow the scale (rounded up to a power of two, at least 256)."""
    scaler = ResolutionScale(15.0)
    shadows = {}
    for scale in (1.0, 0.75, 0.5, 0.3, 0.25, 0.125):
        scaler.scale = scale
        shadows[scale] = scaler.shadow_resolution(1024)
    assert shadows == {1.0: 1024, 0.75: 1024, 0.5: 512, 0.3: 512, 0.25: 256, 0.125: 256}


def test_a_shadow_resolution_out_of_range_is_one_clear_error():
    from cityshade.render import RenderSettings

    with pytest.raises(UsageError, match="shadow_resolution 8: give texels per side, 16 to 8192"):
        RenderSettings(shadow_resolution=8)


def _stepped_cost(fixed: float, full: float, gain: float):
    """Seconds per frame at (scale, quality level): the fixed part shrinks by `gain` per step."""
    return lambda scale, level: fixed / gain**level + full * scale * scale


def _run_stepped(scaler: ResolutionScale, cost, frames: int) -> list[tuple[float, int]]:
    states = []
    for _ in range(frames):
        scaler.update(cost(scaler.scale, scaler.level))
        states.append((scaler.scale, scaler.level))
    return states


def test_quality_steps_are_taken_below_the_smallest_scale_until_the_target_is_met():
    """0.1 s of fixed cost misses 15 fps at any scale; each step takes a fifth off it: the scale
    goes to its minimum first, then steps are taken one by one until the rate reaches the target."""
    scaler = ResolutionScale(15.0, steps=5)
    cost = _stepped_cost(0.1, 0.2, 1.25)
    states = _run_stepped(scaler, cost, 90)
    levels = [level for _, level in states]
    first = levels.index(1)
    assert states[first - 1][0] == scaler.minimum, "steps come after the resolution's minimum"
    assert levels == sorted(levels), "taken one by one, never released while too slow"
    assert len(set(states[-30:])) == 1, "settled"
    level = states[-1][1]
    assert 1 / cost(scaler.minimum, level) >= 15.0 > 1 / cost(scaler.minimum, level - 1), (level, states[-1])


def test_quality_steps_are_released_before_the_scale_rises_when_frames_get_fast():
    scaler = ResolutionScale(15.0, steps=5)
    _run_stepped(scaler, _stepped_cost(0.1, 0.2, 1.25), 90)
    assert scaler.level > 0
    cheap = _stepped_cost(0.005, 0.02, 1.25)  # the view turned to an empty sky
    states = _run_stepped(scaler, cheap, 90)
    released = [level for _, level in states].index(0)
    assert all(scale == scaler.minimum for scale, _ in states[: released + 1]), "steps go first"
    assert states[-1] == (1.0, 0)


def test_a_step_that_overshoots_the_band_is_kept_rather_than_taken_and_released_in_turn():
    """12 fps without the step, 24 with it (past the band of 19.5): releasing it would fall below
    the target again, so it stays."""
    scaler = ResolutionScale(15.0, scale=0.25, steps=1)
    states = _run_stepped(scaler, lambda scale, level: 1 / (24.0 if level else 12.0), 60)
    assert states[scaler.settle - 1] == (0.25, 1) and set(states[scaler.settle - 1 :]) == {(0.25, 1)}


def test_without_steps_the_scale_stops_at_its_minimum():
    scaler = ResolutionScale(15.0)
    states = _run_stepped(scaler, _stepped_cost(0.1, 0.2, 1.25), 60)
    assert states[-1] == (scaler.minimum, 0)


def test_each_quality_step_changes_what_is_drawn_and_adds_to_the_ones_before():
    from cityshade.render import QUALITY_STEPS, RenderSettings, with_quality_steps
    from cityshade.trees import TreeSettings

    full = (RenderSettings(), TreeSettings())
    assert with_quality_steps(*full, 0) == full
    taken = [with_quality_steps(*full, level) for level in range(len(QUALITY_STEPS) + 1)]
    assert all(a != b for a, b in zip(taken, taken[1:])), "every step changes a setting"
    settings, trees = taken[-1]
    assert settings.shadow_refresh == 2 and not settings.relief and not settings.shadows
    assert not trees.relief and not trees.fins and trees.vanish_rows == (12.0, 6.0)


def test_a_shadow_refresh_below_one_is_one_clear_error():
    from cityshade.render import RenderSettings

    with pytest.raises(UsageError, match=r"shadow_refresh 0: give 1 \(the chapter's rates\) or more"):
        RenderSettings(shadow_refresh=0)
