"""`cityshade render` options that change the picture, each seen to change it: footprints, seed,
interiors off, MSAA samples. Marked slow: whole frames through the command line (`make test-slow`)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

FOOTPRINTS = Path(__file__).parents[2] / "examples" / "footprints.geojson"
SIZE = "96x54"
pytestmark = [pytest.mark.slow, pytest.mark.gl]  # renders through the command line


def render_cli(tmp_path: Path, name: str, *args: str) -> np.ndarray:
    out = tmp_path / f"{name}.png"
    result = subprocess.run(
        [sys.executable, "-m", "cityshade", "render", "--size", SIZE, "--out", str(out), *args],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stderr
    image = np.asarray(Image.open(out)).astype(int)
    assert image.shape == (54, 96, 3) and image.std() > 5, f"{name}: a flat picture"
    return image


def changed(a: np.ndarray, b: np.ndarray) -> float:
    """Share of pixels that differ by more than 8/255."""
    return float((np.abs(a - b).max(axis=2) > 8).mean())


def test_seed_changes_the_layout(tmp_path):
    one, two = render_cli(tmp_path, "seed1", "--seed", "1"), render_cli(tmp_path, "seed2", "--seed", "2")
    assert changed(one, two) > 0.1


def test_no_interiors_changes_only_windows(tmp_path):
    rooms = render_cli(tmp_path, "rooms", "--city", "interior", "--camera", "front", "--lights", "0.6")
    plain = render_cli(
        tmp_path, "plain", "--city", "interior", "--camera", "front", "--lights", "0.6", "--no-interiors"
    )
    assert 0.02 < changed(rooms, plain) < 0.8


def test_footprints_render_the_file(tmp_path):
    city = render_cli(tmp_path, "footprints", "--footprints", str(FOOTPRINTS))
    default = render_cli(tmp_path, "default")
    assert changed(city, default) > 0.1


@pytest.mark.parametrize("samples", ["2", "8"])
def test_msaa_samples_smooth_edges_only(tmp_path, samples):
    aliased = render_cli(tmp_path, "s0", "--city", "interior", "--camera", "corner", "--samples", "0")
    smooth = render_cli(tmp_path, f"s{samples}", "--city", "interior", "--camera", "corner", "--samples", samples)
    share = changed(aliased, smooth)
    assert 0.0 < share < 0.3, f"--samples {samples} changed {share:.1%} of the pixels"
