"""Dynamic resolution: the share of the window's pixels a frame is drawn at, chosen from measured
frame times so that frames come at a target rate (the frame's cost is mostly per pixel); below
the smallest scale, quality steps (render/_quality.py) taken one by one."""

from __future__ import annotations

import math
import statistics
from dataclasses import dataclass, field

from ..errors import UsageError

SCALE_STEP = 1 / 32  # scales are multiples of this: tiny changes would only churn the targets


@dataclass
class ResolutionScale:
    """The internal resolution's scale (of width and of height) for a target frame rate.

    It takes the median time of every `settle` frames. Below the target it scales down, aiming a
    little above the target (`target * (1 + band / 6)`); above `target * (1 + band)` it scales up, aiming at
    `target * (1 + band / 2)`; in between it keeps the scale (hysteresis, so it does not hunt).
    The scale stays within [minimum, 1].

    At the minimum scale and still below the target, it takes the next of `steps` quality steps
    (`level` counts those taken); above the band it releases the last one first, before scaling up,
    but only if the frame rate it measured just before taking that step, scaled by how much faster
    frames have become since, stays above its aim: a step that lifts the rate past the band is
    kept rather than taken and released in turn."""

    target_fps: float
    minimum: float = 0.25
    band: float = 0.3
    settle: int = 3
    scale: float = 1.0
    steps: int = 0
    level: int = 0
    _frames: list[float] = field(default_factory=list, repr=False)
    _gains: list[float] = field(default_factory=list, repr=False)  # frame rate with / without each step taken
    _before: float | None = field(default=None, repr=False)  # the rate before the step just taken

    def __post_init__(self):
        if not (self.target_fps > 0 and math.isfinite(self.target_fps)):
            raise UsageError(f"target frame rate {self.target_fps!r}: give a positive number of frames per second")
        if not 0 < self.minimum <= 1:
            raise UsageError(f"minimum resolution scale {self.minimum!r}: give a share in (0, 1]")
        self.scale = self._clamp(self.scale)

    def _clamp(self, scale: float) -> float:
        """Down to a whole step (a frame a little faster than aimed at, never slower), within bounds."""
        steps = math.floor(scale / SCALE_STEP + 1e-9)
        return min(1.0, max(self.minimum, steps * SCALE_STEP))

    def update(self, seconds: float) -> float:
        """Takes the last frame's time (seconds); returns the scale for the next frame."""
        self._frames.append(seconds)
        if len(self._frames) < self.settle:
            return self.scale
        fps = 1.0 / max(statistics.median(self._frames), 1e-9)
        self._frames.clear()
        if self._before is not None:  # the first frames with the step just taken: what it gained
            self._gains.append(max(1.0, fps / self._before))
            self._before = None
        if fps < self.target_fps:
            if self.scale <= self.minimum and self.level < self.steps:
                self.level += 1
                self._before = fps
                return self.scale
            aim = self.target_fps * (1 + self.band / 6)
        elif fps > self.target_fps * (1 + self.band):
            if self.level > 0:
                if fps / self._gains[-1] >= self.target_fps * (1 + self.band / 6):
                    self.level -= 1
                    self._gains.pop()
                return self.scale
            aim = self.target_fps * (1 + self.band / 2)
        else:
            return self.scale
        # frame time ~ pixels ~ scale squared
        self.scale = self._clamp(self.scale * math.sqrt(fps / aim))
        return self.scale

    def shadow_resolution(self, full: int, smallest: int = 256) -> int:
        """Texels per side of a shadow cascade for `full` at scale 1: scaled with the frame (each
        texel keeps covering as many window pixels once the frame is stretched), up to a power of two."""
        return min(full, max(smallest, 1 << math.ceil(math.log2(full * self.scale))))

    def size(self, window: tuple[int, int]) -> tuple[int, int]:
        """The internal resolution for a window of `window` pixels (at least one pixel each way)."""
        return max(1, round(window[0] * self.scale)), max(1, round(window[1] * self.scale))
