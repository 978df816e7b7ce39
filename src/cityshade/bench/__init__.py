"""Benchmarks that reproduce the papers' experiments; `cityshade bench NAME`."""

from ._harness import write

__all__ = ["write"]
