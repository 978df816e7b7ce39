"""Benchmarks that reproduce the papers' experiments; `cityshade bench NAME`."""
