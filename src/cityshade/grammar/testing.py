"""What the tests use of cityshade.grammar's internals: its numpy twins and the parts they check one by one."""

from ._cache import BORDER, CONTENT, FINEST_TEXEL, MAX_PROBES, PAGE, needed_pages, page_hash, page_table
from ._random import facade_cells
from ._reference import facade_view
from ._syntax import parse_text

__all__ = [
    "BORDER",
    "CONTENT",
    "FINEST_TEXEL",
    "MAX_PROBES",
    "PAGE",
    "facade_cells",
    "facade_view",
    "needed_pages",
    "page_hash",
    "page_table",
    "parse_text",
]
