"""The nesting depth of a JSON document, measured before it is parsed.

json.loads recurses once per level of arrays and objects, so a document nested a few thousand deep
ends in a RecursionError at whatever depth the interpreter's stack allows. Measuring first gives a
chosen limit instead, in linear time and without recursion: escaped backslashes and quotes are
dropped, then every byte but brackets and quotes, then the strings (brackets inside them do not
count), and the brackets left are summed. On valid JSON the result is exact; on invalid JSON it may
be anything, and the parser reports the syntax error.
"""

from __future__ import annotations

import re

import numpy as np

# The formats read nest at most ten deep (a CityJSON CompositeSolid: document, CityObjects, object,
# geometry list, geometry, then solids, shells, surfaces, rings, indices); 64 leaves room for
# nested attributes and stays far below the interpreter's recursion limit (1000).
MAX_DEPTH = 64
_NOT_STRUCTURE = bytes(c for c in range(256) if c not in b'[]{}"')
_STRING = re.compile(rb'"[^"]*"')
_CHUNK = 1 << 24  # brackets summed at a time: the running depth takes 4 bytes each


def nesting_depth(data: bytes | str) -> int:
    """How deep arrays and objects nest in the JSON `data` (0 for a bare number or string)."""
    if isinstance(data, str):
        data = data.encode("utf-8", "surrogatepass")
    structure = data.replace(b"\\\\", b"").replace(b'\\"', b"").translate(None, _NOT_STRUCTURE)
    brackets = np.frombuffer(_STRING.sub(b"", structure.replace(b'""', b"")), np.uint8)
    deepest, level = 0, 0
    for start in range(0, len(brackets), _CHUNK):
        chunk = brackets[start : start + _CHUNK]
        steps = ((chunk == ord("[")) | (chunk == ord("{"))).astype(np.int8) - (
            (chunk == ord("]")) | (chunk == ord("}"))
        )
        levels = level + np.cumsum(steps, dtype=np.int32)
        deepest, level = max(deepest, int(levels.max())), int(levels[-1])
    return deepest


def check_depth(data: bytes | str, limit: int = MAX_DEPTH) -> None:
    """Raises ValueError (a phrase to put after the file's name) when `data` nests deeper than `limit`."""
    if nesting_depth(data) > limit:
        raise ValueError(f"arrays and objects nested more than {limit} levels deep")


def value_depth(value) -> int:
    """How deep lists and dicts nest in a parsed value (0 for a scalar), level by level rather than
    by recursion: a document's keys can nest tables that its brackets do not show (TOML's dotted keys)."""
    depth, level = 0, [value]
    while level := [item for item in level if isinstance(item, (dict, list))]:
        depth += 1
        level = [child for item in level for child in (item.values() if isinstance(item, dict) else item)]
    return depth
