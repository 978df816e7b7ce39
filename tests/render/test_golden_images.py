"""The golden-image tolerance itself: it accepts the same picture, rejects small local changes,
and regenerating skips instead of comparing an image with itself."""

import numpy as np
import pytest
from PIL import Image

from golden_images import check_golden, golden_difference

RNG = np.random.default_rng(4)
PICTURE = RNG.integers(40, 200, (96, 128, 3)).astype(np.uint8)


def test_the_same_picture_passes_and_tiny_noise_passes():
    assert golden_difference(PICTURE, PICTURE) is None
    noisy = np.clip(PICTURE.astype(int) + RNG.integers(-1, 2, PICTURE.shape), 0, 255).astype(np.uint8)
    assert golden_difference(noisy, PICTURE) is None


@pytest.mark.parametrize("change", ["hole", "bright patch", "shift", "black"])
def test_local_and_global_changes_fail(change):
    image = PICTURE.copy()
    if change == "hole":
        image[42:54, 58:70] = 0
    elif change == "bright patch":
        image[10:22, 10:22] = np.clip(image[10:22, 10:22].astype(int) + 40, 0, 255)
    elif change == "shift":
        image = np.roll(image, 1, axis=1)
    else:
        image[:] = 0
    assert golden_difference(image, PICTURE) is not None


def test_regenerating_skips_the_comparison(tmp_path, monkeypatch):
    monkeypatch.setenv("CITYSHADE_UPDATE_GOLDEN", "1")
    with pytest.raises(pytest.skip.Exception):
        check_golden(PICTURE, tmp_path / "golden.png")
    assert np.array_equal(np.asarray(Image.open(tmp_path / "golden.png")), PICTURE)
