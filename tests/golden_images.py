"""Golden-image comparison shared by the technique tests: a tolerance, regenerated only on purpose
(CITYSHADE_UPDATE_GOLDEN=1)."""

import os
from pathlib import Path

import numpy as np
from PIL import Image


def check_golden(image: np.ndarray, path: Path):
    """Asserts that `image` matches the golden PNG at `path` (written first when regenerating)."""
    if os.environ.get("CITYSHADE_UPDATE_GOLDEN"):
        path.parent.mkdir(parents=True, exist_ok=True)
        Image.fromarray(image).save(path)
    expected = np.asarray(Image.open(path)).astype(int)
    diff = np.abs(image.astype(int) - expected).max(axis=2)
    assert diff.mean() < 1.5, f"mean difference {diff.mean():.2f}/255"
    assert (diff > 24).mean() < 0.01, f"{(diff > 24).sum()} pixels differ by more than 24/255"
