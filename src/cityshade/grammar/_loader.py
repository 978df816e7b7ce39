"""Reads grammar files: text checks (empty, binary), `use` includes and their namespaces.

`use "brick.grammar" as Brick` copies every rule of brick.grammar into the namespace `Brick`
(§6 "Usability"): inside it names resolve to `Brick.Name`, and the including file may redefine
`Brick.Name` to vary one part of the style without copying the rest.

A `use` names a `.grammar` file in the including file's folder (or below it) or a library style;
it never leaves that folder, so a grammar cannot make cityshade read, or quote in an error, any
other file. An included file that does not parse is reported without quoting its lines.
"""

from __future__ import annotations

import codecs
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from .._files import InputError, read_input_bytes
from ._diagnostics import Diagnostic, GrammarError, Location, shorten
from ._syntax import RuleDef, SourceFile, parse_text

GRAMMAR_SUFFIX = ".grammar"
MAX_GRAMMAR_BYTES = 1 << 20  # the whole library is 10 KB; a megabyte of rules would not fit the texture anyway


@dataclass(frozen=True)
class SourceRule:
    """A rule with its full (namespaced) name and the namespace its own references resolve in."""

    name: str
    namespace: str
    definition: RuleDef

    def resolve(self, reference: str) -> str:
        return f"{self.namespace}.{reference}" if self.namespace else reference


@dataclass
class SourceGrammar:
    """Every rule of a file and its includes, in order; `start` is the file's first rule."""

    path: str
    rules: dict[str, SourceRule]
    start: str
    sources: dict[str, str] = field(default_factory=dict)


def library_path(name: str) -> Path:
    """A file of the bundled style library, e.g. 'fig12.grammar'."""
    return Path(str(resources.files("cityshade.grammar").joinpath("library", name)))


def read_source(path: Path) -> str:
    """The file's text, refusing binary and empty files with a located message."""
    where = Location(str(path), 1, 1)
    try:
        data = read_input_bytes(path, MAX_GRAMMAR_BYTES, "grammar file")
    except InputError as exc:
        raise GrammarError([Diagnostic(where, exc.reason)], {}) from None
    if b"\0" in data:
        raise GrammarError(
            [
                Diagnostic(
                    where,
                    "this is a binary file, not a grammar",
                    "grammar files are UTF-8 text with rules Name->Operator(args)",
                )
            ]
        )
    data = data.removeprefix(codecs.BOM_UTF8)  # editors on Windows start UTF-8 files with one
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise GrammarError(
            [Diagnostic(Location(str(path), line, column), "the file is not UTF-8 text", "save the grammar as UTF-8")]
        ) from None
    return text


def load_source(path: str | Path) -> SourceGrammar:
    """Parses a file and everything it uses into one namespaced rule table."""
    path = Path(path)
    sources: dict[str, str] = {}
    rules, start = _collect(_parse_file(path, sources, quote_syntax_errors=True), path, path.parent, "", sources, [])
    return SourceGrammar(str(path), rules, start, sources)


def parse_string(text: str, name: str = "<string>") -> SourceGrammar:
    """A grammar from text; its `use` lines may name library styles only."""
    sources = {name: text}
    rules, start = _collect(parse_text(text, name), Path(name), None, "", sources, [])
    return SourceGrammar(name, rules, start, sources)


def _include(path: Path, namespace: str, sources: dict[str, str], chain: list[Path]) -> dict[str, SourceRule]:
    """An included file's rules. Its text is quoted in later errors only once it parsed as a grammar."""
    return _collect(
        _parse_file(path, sources, quote_syntax_errors=False), path, path.parent, namespace, sources, chain
    )[0]


def _parse_file(path: Path, sources: dict[str, str], quote_syntax_errors: bool) -> SourceFile:
    """Parses a file; its lines may be quoted in errors only if it is a .grammar file, and, for
    syntax errors, only if asked (the file named on the command line, not an included one)."""
    text = read_source(path)
    quoted = _quotable(path)
    try:
        parsed = parse_text(text, str(path))
    except GrammarError as exc:
        if quoted and quote_syntax_errors:
            raise
        raise GrammarError(exc.diagnostics, {}) from None
    if quoted:
        sources[str(path)] = text
    return parsed


def _quotable(path: Path) -> bool:
    """Whether errors may quote the file's lines: a .grammar file in its folder (or below), also once
    links are resolved. The name alone would quote the first line of `x.grammar` -> /etc/shadow."""
    real = path.resolve()
    return path.suffix == real.suffix == GRAMMAR_SUFFIX and path.parent.resolve() in real.parents


def _collect(
    parsed: SourceFile, path: Path, folder: Path | None, namespace: str, sources: dict[str, str], chain: list[Path]
):
    where = Location(str(path), 1, 1)
    if not parsed.rules and not parsed.uses:
        raise GrammarError(
            [
                Diagnostic(
                    where,
                    "the grammar is empty: it defines no rules",
                    "add rules like Facade->SplitY(Abs, 3.0, Ground, Rel, 1.0, Upper)",
                )
            ],
            sources,
        )
    errors: list[Diagnostic] = []
    included: dict[str, SourceRule] = {}
    seen_namespaces: dict[str, Location] = {}
    for use in parsed.uses:
        if use.namespace in seen_namespaces:
            errors.append(
                Diagnostic(
                    use.location,
                    f"namespace '{use.namespace}' is used twice",
                    "give each included file its own namespace",
                )
            )
            continue
        seen_namespaces[use.namespace] = use.location
        if not use.file.endswith(GRAMMAR_SUFFIX):
            errors.append(
                Diagnostic(
                    use.location,
                    f"'{shorten(use.file)}' is not a {GRAMMAR_SUFFIX} file",
                    f"a grammar may only use other {GRAMMAR_SUFFIX} files",
                )
            )
            continue
        target = _find_include(folder, use.file)
        if target is None:
            where_from = f"{folder or '.'} (or a folder below it)" if folder is not None else "nowhere but the library"
            errors.append(
                Diagnostic(
                    use.location,
                    f"included file '{shorten(use.file)}' not found",
                    f"a use names a file in {where_from} or a library style",
                )
            )
            continue
        if target.resolve() in [p.resolve() for p in chain + [path]]:
            cycle = " -> ".join(p.name for p in chain + [path, target])
            errors.append(Diagnostic(use.location, f"files include each other: {cycle}"))
            continue
        full_ns = f"{namespace}.{use.namespace}" if namespace else use.namespace
        included.update(_include(target, full_ns, sources, chain + [path]))
    own: dict[str, SourceRule] = {}
    for rule in parsed.rules:
        full = f"{namespace}.{rule.name}" if namespace else rule.name
        if full in own:
            first = own[full].definition.location
            errors.append(
                Diagnostic(
                    rule.location,
                    f"rule '{rule.name}' is defined twice",
                    f"the first definition is at line {first.line}; rename one of them",
                )
            )
            continue
        own[full] = SourceRule(full, namespace, rule)
    if errors:
        raise GrammarError(errors, sources)
    merged = dict(included)
    merged.update(own)  # the including file's definitions override the included ones
    start = next(iter(own)) if own else next(iter(included))
    return merged, start


def _find_include(folder: Path | None, name: str) -> Path | None:
    """The file a `use` names, only if it lies inside `folder` (links resolved) or the library."""
    if "\0" in name:  # no file has such a name (and the OS refuses to look it up)
        return None
    library = library_path("")
    roots = ([folder] if folder is not None else []) + [library]
    for root in roots:
        candidate = root / name
        inside = Path(root).resolve()
        if not Path(name).is_absolute() and inside in candidate.resolve().parents and candidate.resolve().is_file():
            return candidate
    return None
