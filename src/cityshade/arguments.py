"""Command-line arguments shared by every command: parsing sizes, metres and shares, and checking
and writing output files. Technique packages import these from here, not from each other."""

from __future__ import annotations

import os
import re
from pathlib import Path

from ._files import atomic_output
from .errors import UsageError


def parse_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"(\d+)x(\d+)", text.strip())
    if not match or not (1 <= int(match.group(1)) <= 16384 and 1 <= int(match.group(2)) <= 16384):
        raise UsageError(f"invalid size {text!r}; use WIDTHxHEIGHT with each from 1 to 16384, e.g. 1280x720")
    return int(match.group(1)), int(match.group(2))


def parse_metres(text: str, option: str = "--facade", limit: float = 4096.0) -> tuple[float, float]:
    """'20x16' -> (20.0, 16.0) metres, each side in (0, limit]."""
    try:
        width, height = (float(v) for v in text.lower().split("x"))
    except ValueError:
        raise UsageError(f"invalid {option} {text!r}; use WIDTHxHEIGHT in metres, e.g. 20x16") from None
    if not (0 < width <= limit and 0 < height <= limit):
        raise UsageError(f"invalid {option} {text!r}; each side must be in (0, {limit:g}] metres")
    return width, height


def parse_lights(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value <= 1.0:
        raise UsageError(f"invalid --lights {text!r}; the share of lit rooms is a number from 0 to 1")
    return value


def check_writable(path: Path) -> Path:
    """Fails early, with one line, if the output cannot be written (nothing is created)."""
    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise UsageError(f"output path {str(path)!r} is a directory; give a file name such as out/city.png")
    probe = folder
    while not probe.exists():
        probe = probe.parent
    if not os.access(probe, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise UsageError(f"cannot write {str(path)!r}: permission denied; choose another --out")
    if not probe.is_dir():
        raise UsageError(f"cannot write {str(path)!r}: {str(probe)!r} is not a directory")
    return path


def save_png(image, path: Path):
    """Writes atomically: a finished PNG or nothing."""
    from PIL import Image

    with atomic_output(path) as tmp:
        Image.fromarray(image).save(tmp, format="PNG")
