"""The text syntax of §3 / fig. 12, parsed with lark into rules that remember where they were written.

    # comment
    use "brick.grammar" as Brick          # namespace: Brick.Rule names the included rules
    S->Layer(Wall, Assets)
    Assets->SplitY(Abs, 3.0, BottomFloor,
                   Rel, 1.0, Middle);     # arguments may span lines, ';' is optional
    Wall1->Mat(Color, Rep:wall1, 0.0, 0.0, 1.0, 1.0)
    Window->Wall1                         # an alias: Window is Wall1
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from lark import Lark, Token, UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ._diagnostics import Diagnostic, GrammarError, Location, shorten
from ._operators import ALIAS

_LARK_GRAMMAR = r"""
start: _item*
_item: rule | use
use: USE STRING AS NAME ";"?
rule: NAME ARROW NAME "(" [arg ("," arg)*] ")" ";"?
    | NAME ARROW NAME ";"? -> alias
arg: NUMBER -> number
   | TEXREF -> texref
   | NAME -> name
USE.2: "use"
AS.2: "as"
ARROW: "->"
TEXREF.3: /(Rep:|Fit>)[A-Za-z_][A-Za-z0-9_]*/
NAME: /[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*/
NUMBER: /[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/
STRING: /"[^"\n]*"/
COMMENT: /#[^\n]*/
%import common.WS
%ignore WS
%ignore COMMENT
"""

_TOKEN_WORDS = {
    "ARROW": "'->'", "LPAR": "'('", "RPAR": "')'", "COMMA": "','", "SEMICOLON": "';'",
    "NAME": "a name", "NUMBER": "a number", "TEXREF": "a texture Rep:name or Fit>name",
    "STRING": "a quoted file name", "USE": "'use'", "AS": "'as'", "$END": "the end of the file",
}


@dataclass(frozen=True)
class Arg:
    """One argument as written: kind is 'number', 'name' or 'texref'."""

    kind: str
    text: str
    location: Location

    @property
    def value(self) -> float:
        return float(self.text)


@dataclass(frozen=True)
class RuleDef:
    name: str
    operator: str
    args: tuple[Arg, ...]
    location: Location  # of the rule name
    operator_location: Location


@dataclass(frozen=True)
class UseDef:
    file: str
    namespace: str
    location: Location


@dataclass(frozen=True)
class SourceFile:
    path: str
    rules: tuple[RuleDef, ...]
    uses: tuple[UseDef, ...]


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return Lark(_LARK_GRAMMAR, parser="lalr", propagate_positions=True, maybe_placeholders=False)


def _loc(path: str, token: Token) -> Location:
    return Location(path, token.line, token.column, max(len(str(token)), 1))


def parse_text(text: str, path: str) -> SourceFile:
    """Parses one file's text; syntax errors raise GrammarError naming file:line:col."""
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as exc:
        raise GrammarError([_syntax_diagnostic(exc, text, path)], {path: text}) from None
    rules, uses = [], []
    for node in tree.children:
        if node.data == "use":
            _, file_tok, _, ns_tok = node.children
            uses.append(UseDef(str(file_tok)[1:-1], str(ns_tok), _loc(path, ns_tok)))
            continue
        name_tok, arrow_tok, op_tok, *arg_nodes = node.children
        if node.data == "alias":  # A->B: the operator is the arrow, its one argument the target
            args = (Arg("name", str(op_tok), _loc(path, op_tok)),)
            rules.append(RuleDef(str(name_tok), ALIAS, args, _loc(path, name_tok), _loc(path, arrow_tok)))
            continue
        args = tuple(Arg(a.data, str(a.children[0]), _loc(path, a.children[0])) for a in arg_nodes)
        rules.append(RuleDef(str(name_tok), str(op_tok), args, _loc(path, name_tok), _loc(path, op_tok)))
    return SourceFile(path, tuple(rules), tuple(uses))


def _syntax_diagnostic(exc: UnexpectedInput, text: str, path: str) -> Diagnostic:
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        lines = text.rstrip().split("\n") or [""]
        loc = Location(path, len(lines), len(lines[-1]) + 1)
        expected = _expected_words(getattr(exc, "expected", ()))
        return Diagnostic(loc, f"the file ends in the middle of a rule; expected {expected}",
                          "close the argument list with ')'")
    if isinstance(exc, UnexpectedCharacters):
        char = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else "?"
        loc = Location(path, exc.line, exc.column)
        hint = "rules look like Name->Operator(arg, ...); '#' starts a comment"
        if char in ":>" :
            hint = "texture references are written Rep:name (tiled) or Fit>name (fitted)"
        return Diagnostic(loc, f"unexpected character {char!r}", hint)
    token = exc.token
    loc = Location(path, token.line, token.column, max(len(str(token)), 1))
    expected = _expected_words(exc.expected)
    hint = ""
    if token.type == "NAME" and "ARROW" in exc.expected:
        hint = "a rule is written Name->Operator(args); is '->' missing?"
    elif token.type == "NAME" and "COMMA" in exc.expected:
        hint = "is a ',' missing between arguments?"
    return Diagnostic(loc, f"unexpected {shorten(str(token))!r}; expected {expected}", hint)


def _expected_words(expected) -> str:
    words = sorted({_TOKEN_WORDS.get(e, e) for e in expected})
    return " or ".join(words) if words else "something else"
