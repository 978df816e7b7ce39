"""Golden-image comparison shared by the technique tests: a tolerance, regenerated only on purpose
(CITYSHADE_UPDATE_GOLDEN=1, which writes the images and skips the comparison: an image compared
with itself proves nothing).

The tolerance is global (mean difference, share of pixels off by more than 24/255) and block-local:
no 8x8 block may differ by more than 12/255 on average, so a small feature that changes (a 12x12
hole, the bark relief on a trunk) fails even when the rest of the picture is unchanged.
"""

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

BLOCK = 8
BLOCK_LIMIT = 12.0  # mean difference in one block, /255
MEAN_LIMIT = 1.5
FAR_OFF, FAR_OFF_SHARE = 24, 0.01


def regenerating() -> bool:
    return bool(os.environ.get("CITYSHADE_UPDATE_GOLDEN"))


def load_golden(path: Path) -> np.ndarray:
    return np.asarray(Image.open(path))


def block_means(diff: np.ndarray, block: int = BLOCK) -> np.ndarray:
    """Mean of `diff` (H, W) over each block x block tile (the last partial row and column kept)."""
    h, w = diff.shape
    padded = np.full((-(-h // block) * block, -(-w // block) * block), np.nan)
    padded[:h, :w] = diff
    tiles = padded.reshape(padded.shape[0] // block, block, padded.shape[1] // block, block)
    return np.nanmean(tiles, axis=(1, 3))


def golden_difference(image: np.ndarray, expected: np.ndarray) -> str | None:
    """Why `image` does not match `expected` (uint8 RGB), or None when it does."""
    assert image.shape == expected.shape, f"image {image.shape} against golden {expected.shape}"
    diff = np.abs(image.astype(int) - expected.astype(int)).max(axis=2)
    blocks = block_means(diff)
    reasons = []
    if diff.mean() >= MEAN_LIMIT:
        reasons.append(f"mean difference {diff.mean():.2f}/255")
    if (diff > FAR_OFF).mean() >= FAR_OFF_SHARE:
        reasons.append(f"{(diff > FAR_OFF).sum()} pixels differ by more than {FAR_OFF}/255")
    if blocks.max() > BLOCK_LIMIT:
        y, x = np.unravel_index(np.argmax(blocks), blocks.shape)
        reasons.append(
            f"{int((blocks > BLOCK_LIMIT).sum())} {BLOCK}x{BLOCK} blocks differ by more than "
            f"{BLOCK_LIMIT:g}/255 on average (worst {blocks.max():.1f} at x={x * BLOCK}, y={y * BLOCK})"
        )
    return "; ".join(reasons) or None


def check_golden(image: np.ndarray, path: Path):
    """Asserts that `image` matches the golden PNG at `path`; when regenerating, writes it and skips."""
    if regenerating():
        path.parent.mkdir(parents=True, exist_ok=True)
        Image.fromarray(image).save(path)
        pytest.skip(f"regenerated {path}: look at it, then run the tests without CITYSHADE_UPDATE_GOLDEN")
    reason = golden_difference(image, load_golden(path))
    assert reason is None, f"{path.name}: {reason}"


def check_golden_rejects(image: np.ndarray, path: Path, what: str):
    """Asserts that the golden at `path` does NOT accept `image` (a render with a guarded feature off)."""
    if regenerating():
        pytest.skip("goldens are being regenerated")
    reason = golden_difference(image, load_golden(path))
    assert reason is not None, f"{path.name} accepts a render with {what}: the golden cannot see that feature"
    print(f"{path.name} rejects {what}: {reason}")
