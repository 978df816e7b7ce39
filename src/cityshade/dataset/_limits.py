"""The caps of `cityshade dataset` and the checks behind them, in one place (docs/datasets.md,
docs/robustness.md). Every cap is checked before anything is written."""

from __future__ import annotations

import os
import re
import reprlib

# The driver computes every view up front and holds every manifest row (measured: about 0.4 kB a
# view and 1 kB a row, 1.4 GB at the cap) and rewrites the whole manifest every 2 s (about 10 s at
# a million rows); a larger dataset belongs in several folders (seeds). The 7-digit file names
# would run out at 10 million.
MAX_SAMPLES = 1_000_000
# Each actor requests one CPU. Locally llvmpipe's threads already share out every core
# (LP_NUM_THREADS = cores / K): two actors a core keep one rendering while the other writes its
# files, more only add memory (each holds the city and a renderer: 0.36 GB for Helsinki).
WORKERS_PER_CORE = 2
# numpy seeds its generator with [seed, index]; 64-bit so that other tools read dataset.json's seed.
MAX_SEED = 2**63 - 1
# A config or dataset.json is a few hundred bytes; the deepest value either holds is a [low, high]
# pair in a section (three levels). 64 levels, as for every JSON cityshade reads, leave room for a
# mistake to be reported as the wrong type of its key, far below where tomllib and json recurse
# out of Python's stack (about a thousand).
MAX_CONFIG_BYTES = 1 << 20
MAX_RECORD_BYTES = 1 << 20
MAX_NESTING = 64
# A manifest holds about 105 bytes a sample on disk (110 MB at MAX_SAMPLES) and about 250 in Arrow.
MAX_MANIFEST_BYTES = 256 << 20
MAX_MANIFEST_UNPACKED = 1 << 30
# The largest file of a sample at the config's largest image (4096 x 4096) is its normal map,
# float32 x 3: 192 MiB and a header.
MAX_SAMPLE_FILE_BYTES = 4096 * 4096 * 3 * 4 + 4096
MAX_IMAGE_SIDE = 4096


def local_cores() -> int:
    """The cores this process may run on (a container's share, not the machine's)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def max_local_workers() -> int:
    return WORKERS_PER_CORE * local_cores()


_SHORT = reprlib.Repr()
_SHORT.maxstring = _SHORT.maxother = 60
_SHORT.maxlevel, _SHORT.maxlist, _SHORT.maxdict = 3, 4, 4


def shown(value) -> str:
    """A value read from a file, for a one-line message: repr, cut short, nesting cut off."""
    return _SHORT.repr(value)


def shown_key(key) -> str:
    """A key read from a file: as it is when it is a short plain name, else shown()."""
    if isinstance(key, str) and re.fullmatch(r"[A-Za-z0-9_.\-]{1,60}", key):
        return key
    return shown(key)


# After an opening quote: the rest of the string to its closing quote. Linear: no alternative
# overlaps another, and a string that does not close ends the scan, as it ends the parser.
_TOML_STRINGS = {
    '"': re.compile(r'(?:[^"\\\n]|\\.)*"'),
    "'": re.compile(r"[^'\n]*'"),
    '"""': re.compile(r'(?:[^"\\]|\\.|"(?!""))*"""', re.S),
    "'''": re.compile(r"(?:[^']|'(?!''))*'''", re.S),
}
_TOML_NEXT = re.compile(r"[\"'#\[\]{}]")


def toml_nesting(text: str) -> int:
    """How deep arrays and inline tables nest in TOML text (a table header counts its brackets),
    in linear time, before tomllib recurses into them; past MAX_NESTING the count stops."""
    depth = deepest = i = 0
    while (found := _TOML_NEXT.search(text, i)) is not None:
        c, i = found.group(), found.end()
        if c == "#":
            i = text.find("\n", i)
            if i < 0:
                break
        elif c in "\"'":
            quote = c * 3 if text.startswith(c * 2, i) else c
            end = _TOML_STRINGS[quote].match(text, i + len(quote) - 1)
            if end is None:  # the parser stops here too
                break
            i = end.end()
            if len(quote) == 3:  # up to two more quotes before the closing three are the string's
                i += 2 if text.startswith(c * 2, i) else 1 if text.startswith(c, i) else 0
        elif c in "[{":
            depth += 1
            deepest = max(deepest, depth)
            if deepest > MAX_NESTING:
                break
        else:
            depth = max(0, depth - 1)
    return deepest
