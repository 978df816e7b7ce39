"""Progress of a run: rich's bar on a terminal, plain lines elsewhere (a log file, a notebook, a
CI job), one each time another tenth of the samples is done, and at the end."""

from __future__ import annotations

import contextlib
import sys
import time

STEPS = 10  # lines per run when the output is not a terminal


class ProgressLines:
    """Prints `label: done/total samples (percent), rate` as each tenth of `total` is passed."""

    def __init__(self, label: str, total: int, done: int = 0, stream=None):
        self.label, self.total, self.done = label, total, done
        self.stream = stream or sys.stdout
        self.start, self.first = time.monotonic(), done
        self.step = self._step(done)

    def _step(self, done: int) -> int:
        return done * STEPS // max(self.total, 1)

    def advance(self, count: int):
        self.done += count
        step = self._step(self.done)
        if step > self.step or self.done >= self.total:
            self.step = step
            seconds = time.monotonic() - self.start
            rate = (self.done - self.first) / seconds if seconds > 0 else 0.0
            percent = 100 * self.done // max(self.total, 1)
            print(
                f"{self.label}: {self.done}/{self.total} samples ({percent}%), {rate:.2f} samples/s",
                file=self.stream,
                flush=True,
            )


@contextlib.contextmanager
def progress(label: str, total: int, done: int = 0, enabled: bool = True):
    """Yields advance(count): a rich bar on a terminal, ProgressLines otherwise, nothing if not enabled."""
    if not enabled:
        yield lambda count: None
    elif sys.stdout.isatty():
        from rich.progress import Progress

        with Progress(transient=True) as bar:
            task = bar.add_task(label, total=total, completed=done)
            yield lambda count: bar.advance(task, count)
    else:
        yield ProgressLines(label, total, done).advance
