"""Error messages that point into a grammar file: FILE:LINE:COL, the offending line, a caret, a hint."""

from __future__ import annotations

import difflib
from dataclasses import dataclass

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
        text = (sources or {}).get(loc.path)  # only files that parsed as grammars are quoted
        if text is not None:
            source_lines = text.split("\n")  # as the parser counts lines: '\f' or a bare '\r' do not end one
            if 1 <= loc.line <= len(source_lines):
                shown = "".join(c if c.isprintable() else " " for c in source_lines[loc.line - 1])
                lines.append(f"    {shown}")
                lines.append("    " + " " * (loc.column - 1) + "^" + "~" * max(loc.length - 1, 0))
        if self.hint:
            lines.append(f"    hint: {self.hint}")
        return "\n".join(lines)


def shorten(token: str, limit: int = 40) -> str:
    """A token as quoted in a message: never more than `limit` characters of someone's file."""
    return token if len(token) <= limit else token[: limit - 3] + "..."


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
