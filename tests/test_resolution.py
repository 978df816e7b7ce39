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
