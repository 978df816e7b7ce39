"""What the tests use of cityshade.relief's internals: its numpy twins and the parts they check one by one."""

from ._city import cached_openings
from ._format import _PREFIX, MAGIC
from ._grammar_source import OPENING_DEPTH
from ._layout import WALL
from ._reference import MISS
from ._view import SINGLE_FACADE

__all__ = ["MAGIC", "MISS", "OPENING_DEPTH", "SINGLE_FACADE", "WALL", "_PREFIX", "cached_openings"]
