"""Values the command line and the Python API both accept, checked in one place each, so the
API raises the same UsageError with the same message as the CLI prints."""

from __future__ import annotations

import math
import re

from .errors import UsageError

MAX_SIDE = 16384  # pixels; the usual GL_MAX_TEXTURE_SIZE (renders are also checked against the device's own)
MAX_SEED = 2**31 - 1  # seeds feed 32-bit integer hashes on the GPU
SAMPLES = (0, 2, 4, 8)


def check_size(size) -> tuple[int, int]:
    """(width, height) in pixels, each from 1 to MAX_SIDE."""
    try:
        width, height = (int(v) for v in size)
        valid = all(int(v) == v for v in size) and 1 <= width <= MAX_SIDE and 1 <= height <= MAX_SIDE
    except (TypeError, ValueError, OverflowError):
        valid = False
    if not valid:
        raise UsageError(f"invalid size {_shown(size)}; use WIDTHxHEIGHT with each from 1 to {MAX_SIDE}, e.g. 1280x720")
    return width, height


def parse_time(value: str | float) -> float:
    """A time of day, 'HH:MM' or hours (a number from 0 to under 24), as hours: the one type every
    `time` of the API and the command line goes through."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if math.isfinite(value) and 0.0 <= value < 24.0:
            return float(value)
        match = None
    else:
        match = re.fullmatch(r"(\d{1,2}):(\d{2})", value.strip()) if isinstance(value, str) else None
    if not match or int(match.group(1)) > 23 or int(match.group(2)) > 59:
        raise UsageError(
            f"invalid time {value!r}; use HH:MM from 00:00 to 23:59, e.g. 18:50, or hours from 0 to under 24, e.g. 18.83"
        )
    return int(match.group(1)) + int(match.group(2)) / 60.0


def parse_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"(\d{1,9})x(\d{1,9})", text.strip())
    if not match:
        raise UsageError(f"invalid size {text!r}; use WIDTHxHEIGHT with each from 1 to {MAX_SIDE}, e.g. 1280x720")
    try:
        return check_size((int(match.group(1)), int(match.group(2))))
    except UsageError:
        raise UsageError(
            f"invalid size {text!r}; use WIDTHxHEIGHT with each from 1 to {MAX_SIDE}, e.g. 1280x720"
        ) from None


def check_lights(value) -> float | None:
    """The share of lit rooms, 0..1 (None: from the time of day)."""
    if value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if isinstance(value, bool) or not 0.0 <= number <= 1.0:
        raise UsageError(f"invalid --lights {_shown(value)}; the share of lit rooms is a number from 0 to 1")
    return number


def _whole(value, high: int) -> int | None:
    """`value` as a whole number from 0 to `high`, or None (bools, fractions, text, overflow)."""
    try:
        number = int(value)
        valid = not isinstance(value, bool) and number == float(value) and 0 <= number <= high
    except (TypeError, ValueError, OverflowError):
        return None
    return number if valid else None


def check_seed(value, option: str = "--seed") -> int:
    """A seed from 0 to 2^31 - 1."""
    seed = _whole(value, MAX_SEED)
    if seed is None:
        raise UsageError(f"invalid {option} {_shown(value)}; a seed is a whole number from 0 to {MAX_SEED}")
    return seed


def check_samples(value) -> int:
    if value not in SAMPLES or isinstance(value, bool):
        raise UsageError(f"invalid --samples {_shown(value)}; MSAA samples are one of {', '.join(map(str, SAMPLES))}")
    return int(value)


def check_count(value, option: str) -> int:
    """A whole number from 0 to 2048 (a building attribute: exact in the GPU's 16-bit floats)."""
    count = _whole(value, 2048)
    if count is None:
        raise UsageError(f"invalid {option} {_shown(value)}; give a whole number from 0 to 2048")
    return count


def check_type(value, kind: type, what: str, hint: str):
    """`value` if it is a `kind`; else one line naming it, as the other checks do."""
    if not isinstance(value, kind):
        raise UsageError(f"invalid {what} {_shown(value)}; {hint}")
    return value


def _shown(value) -> str:
    text = repr(value if not isinstance(value, str) else value)
    return text if len(text) <= 40 else text[:37] + "..."
