"""Error messages that point into a grammar file: FILE:LINE:COL, the offending line, a caret, a hint."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from pathlib import Path

from ..errors import CityshadeError


@dataclass(frozen=True)
class Location:
    path: str
    line: int
    column: int
    length: int = 1


@dataclass(frozen=True)
class Diagnostic:
    location: Location
    message: str
    hint: str = ""

    def format(self, sources: dict[str, str] | None = None) -> str:
        loc = self.location
        head = f"{loc.path}:{loc.line}:{loc.column}: error: {self.message}"
        lines = [head]
        text = (sources or {}).get(loc.path)
        if text is None:
            text = _read_quietly(loc.path)
        if text is not None:
            source_lines = text.splitlines()
            if 1 <= loc.line <= len(source_lines):
                shown = source_lines[loc.line - 1].replace("\t", " ")
                lines.append(f"    {shown}")
                lines.append("    " + " " * (loc.column - 1) + "^" + "~" * max(loc.length - 1, 0))
        if self.hint:
            lines.append(f"    hint: {self.hint}")
        return "\n".join(lines)


def _read_quietly(path: str) -> str | None:
    try:
        return Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None


class GrammarError(CityshadeError):
    """One or more problems in grammar files; str() gives every diagnostic, each with its caret."""

    def __init__(self, diagnostics: list[Diagnostic], sources: dict[str, str] | None = None):
        self.diagnostics = list(diagnostics)
        super().__init__("\n".join(d.format(sources) for d in self.diagnostics))


def suggest(name: str, candidates, what: str) -> str:
    """'did you mean ...?' for a misspelt name, or an empty hint."""
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    if not close:
        lowered = {c.lower(): c for c in candidates}
        if name.lower() in lowered:
            close = [lowered[name.lower()]]
    return f"did you mean the {what} '{close[0]}'?" if close else ""
