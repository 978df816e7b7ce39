"""cityshade's version, low enough in the package for the tile cache to record it."""

__version__ = "0.1.0"
