"""A contact sheet of a dataset, for checking its labels by eye: per sample a row of the RGB, the
classes over it, the depth (near bright, far dark) and the building instances over it; a legend
of the class colours at the bottom."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from ..errors import UsageError
from ._classes import CLASS_COLOURS, CLASSES, IGNORE
from ._manifest import read_manifest
from ._sample import write_atomic

LEGEND_ROW = 14


def _overlay(rgb: np.ndarray, colours: np.ndarray, mask: np.ndarray, alpha: float = 0.55) -> np.ndarray:
    out = rgb.astype(np.float32)
    out[mask] = (1 - alpha) * out[mask] + alpha * colours[mask]
    return out.astype(np.uint8)


def _depth_picture(z: np.ndarray) -> np.ndarray:
    finite = np.isfinite(z)
    inverse = np.where(finite, 1.0 / np.maximum(z, 1e-3), 0.0)
    top = np.percentile(inverse[finite], 99) if finite.any() else 1.0
    grey = (np.clip(inverse / max(top, 1e-9), 0, 1) * 255).astype(np.uint8)
    return np.repeat(grey[..., None], 3, axis=-1)


def _instance_colours(instance: np.ndarray) -> np.ndarray:
    h = (instance.astype(np.uint64) * np.uint64(2654435761)) & np.uint64(0xFFFFFF)
    return np.stack([(h >> np.uint64(s)) & np.uint64(255) for s in (0, 8, 16)], axis=-1).astype(np.float32)


def sample_row(folder: Path, row: dict) -> np.ndarray:
    rgb = np.asarray(Image.open(folder / row["rgb"]).convert("RGB"))
    classes = np.asarray(Image.open(folder / row["class"]))
    palette = np.zeros((256, 3), np.float32)
    palette[: len(CLASS_COLOURS)] = CLASS_COLOURS
    instance = np.load(folder / row["instance"])
    depth = np.load(folder / row["depth"])
    return np.concatenate(
        [
            rgb,
            _overlay(rgb, palette[classes], classes != IGNORE),
            _depth_picture(depth),
            _overlay(rgb, _instance_colours(instance), instance > 0),
        ],
        axis=1,
    )


def write_preview(folder: Path, out: Path | None = None, count: int = 8) -> Path:
    """Writes `out` (default folder/preview.png) from the first `count` samples of the manifest."""
    rows = read_manifest(folder)[:count]
    if not rows:
        raise UsageError(f"{folder}: no complete sample to preview; run cityshade dataset --out {folder} first")
    sheet = np.concatenate([sample_row(folder, row) for row in rows], axis=0)
    columns = 4
    per_column = -(-len(CLASSES) // columns)
    legend = Image.new("RGB", (sheet.shape[1], per_column * LEGEND_ROW + 4), (255, 255, 255))
    draw = ImageDraw.Draw(legend)
    width = sheet.shape[1] // columns
    for k, name in enumerate(CLASSES):
        x, y = (k // per_column) * width + 4, (k % per_column) * LEGEND_ROW + 2
        draw.rectangle((x, y, x + 10, y + 10), fill=tuple(int(c) for c in CLASS_COLOURS[k]), outline=(0, 0, 0))
        draw.text((x + 14, y), name, fill=(0, 0, 0))
    picture = Image.new("RGB", (sheet.shape[1], sheet.shape[0] + legend.height))
    picture.paste(Image.fromarray(sheet), (0, 0))
    picture.paste(legend, (0, sheet.shape[0]))
    out = out or folder / "preview.png"
    buffer = io.BytesIO()
    picture.save(buffer, format="PNG")
    write_atomic(out, buffer.getvalue())
    return out
