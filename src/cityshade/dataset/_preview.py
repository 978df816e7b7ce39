"""A contact sheet of a dataset, for checking its labels by eye: per sample a row of the RGB, the
classes over it, the depth (near bright, far dark) and the building instances over it; a legend
of the class colours at the bottom. The samples' files are read as capped regular files inside the
folder and decoded only after their headers say they are images or arrays of the sizes a dataset
holds; anything else is one line naming the manifest row and the column."""

from __future__ import annotations

import io
import warnings
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from ..errors import UsageError
from ._arrays import ArrayFileError, decode
from ._classes import CLASS_COLOURS, CLASSES, IGNORE
from ._limits import MAX_IMAGE_SIDE
from ._manifest import folder_file, read_manifest, read_sample_file, sample_error
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


def _png(folder: Path, row: dict, column: str, mode: str) -> np.ndarray:
    data = read_sample_file(folder, row, column)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            image = Image.open(io.BytesIO(data), formats=["PNG"])
            if max(image.size) > MAX_IMAGE_SIDE or min(image.size) < 1:
                raise sample_error(
                    folder, row, column, f"{image.size[0]}x{image.size[1]} pixels, not a dataset's image"
                )
            if mode == "L" and image.mode != "L":
                raise sample_error(folder, row, column, f"a {image.mode} image, not 8-bit classes")
            return np.asarray(image.convert(mode))
    except UsageError:
        raise
    except (OSError, ValueError, SyntaxError, EOFError, Image.DecompressionBombError, Image.DecompressionBombWarning):
        raise sample_error(folder, row, column, "not a readable PNG image") from None


def _array(folder: Path, row: dict, column: str, kinds: str) -> np.ndarray:
    """A sample's array file (.npz, .exr or an older dataset's .npy), its header checked before the
    array is allocated; an image's first channel (an instance image's building numbers)."""
    data = read_sample_file(folder, row, column)
    try:
        array = decode(data, row[column], kinds)
    except ArrayFileError as exc:
        raise sample_error(folder, row, column, str(exc)) from None
    return array[..., 0] if array.ndim == 3 else array


def sample_row(folder: Path, row: dict) -> np.ndarray:
    rgb = _png(folder, row, "rgb", "RGB")
    classes = _png(folder, row, "class", "L")
    instance = _array(folder, row, "instance", "ui")
    depth = _array(folder, row, "depth", "f")
    for column, array in (("class", classes), ("instance", instance), ("depth", depth)):
        if array.shape[:2] != rgb.shape[:2]:
            raise sample_error(
                folder,
                row,
                column,
                f"{array.shape[1]}x{array.shape[0]}, the RGB image is {rgb.shape[1]}x{rgb.shape[0]}",
            )
    palette = np.zeros((256, 3), np.float32)
    palette[: len(CLASS_COLOURS)] = CLASS_COLOURS
    return np.concatenate(
        [
            rgb,
            _overlay(rgb, palette[classes], classes != IGNORE),
            _depth_picture(depth.astype(np.float32)),
            _overlay(rgb, _instance_colours(instance), instance > 0),
        ],
        axis=1,
    )


def write_preview(folder: Path, out: Path | None = None, count: int = 8) -> Path:
    """Writes `out` (default folder/preview.png) from the first `count` samples of the manifest."""
    rows = read_manifest(folder)[:count]
    if not rows:
        raise UsageError(f"{folder}: no complete sample to preview; run cityshade dataset --out {folder} first")
    pictures = [sample_row(folder, row) for row in rows]
    for row, picture in zip(rows, pictures):
        if picture.shape != pictures[0].shape:
            width, height = picture.shape[1] // 4, picture.shape[0]
            first = f"{pictures[0].shape[1] // 4}x{pictures[0].shape[0]}"
            raise sample_error(folder, row, "rgb", f"{width}x{height} pixels, sample {rows[0]['index']} has {first}")
    sheet = np.concatenate(pictures, axis=0)
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
    buffer = io.BytesIO()
    picture.save(buffer, format="PNG")
    write_atomic(out or folder_file(folder, "preview.png"), buffer.getvalue())
    return out or Path(folder) / "preview.png"
