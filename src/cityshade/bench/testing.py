"""What the tests use of cityshade.bench's internals: its numpy twins and the parts they check one by one."""

from ._harness import MIN_TIMED_FRAMES

__all__ = ["MIN_TIMED_FRAMES"]
