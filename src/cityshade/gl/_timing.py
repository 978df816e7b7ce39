"""Wall-clock frame timing: ctx.finish() around each frame (timer queries mean little on llvmpipe)."""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass, field
from typing import Callable

import moderngl


@dataclass
class FrameTimer:
    ctx: moderngl.Context
    warmup: int = 2
    frames: int = 10
    times: list[float] = field(default_factory=list)

    def run(self, draw: Callable[[int], None]) -> float:
        """Calls draw(frame_index) warmup + frames times; returns the median seconds per frame."""
        for i in range(self.warmup):
            draw(i)
        self.ctx.finish()
        self.times = []
        for i in range(self.frames):
            t0 = time.perf_counter()
            draw(self.warmup + i)
            self.ctx.finish()
            self.times.append(time.perf_counter() - t0)
        return statistics.median(self.times)
