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

from lark import Lark, Token, Tree, UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ._diagnostics import Diagnostic, GrammarError, Location, shorten
from ._expressions import Expr
from ._operators import ALIAS

_LARK_GRAMMAR = r"""
start: _item*
_item: rule | use
use: USE STRING AS NAME ";"?
rule: NAME [params] ARROW NAME "(" [expr ("," expr)*] ")" ";"?
    | NAME [params] ARROW NAME ";"? -> alias
params: "(" NAME ("," NAME)* ")"
?expr: expr OROR conj -> binary
     | conj
?conj: conj ANDAND comparison -> binary
     | comparison
?comparison: sum COMPARE sum -> binary
           | sum
?sum: sum ADDOP term -> binary
    | term
?term: term MULOP unary -> binary
     | unary
?unary: NOT unary -> not_
      | ADDOP unary -> neg
      | atom
?atom: NUMBER -> number
     | TEXREF -> texref
     | NAME -> name
     | NAME "(" [expr ("," expr)*] ")" -> call
     | "(" expr ")"
OROR: "||"
ANDAND: "&&"
COMPARE: "==" | "!=" | "<=" | ">=" | "<" | ">"
ADDOP: "+" | "-"
MULOP: "*" | "/" | "%"
NOT: "!"
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

# Arguments nest (calls, brackets, operators) at most this deep: the passes that read them recurse
# once per level, and a grammar's conditions fit the GPU's 8-slot stack and 4 nested Layers anyway.
MAX_NESTING = 64

_TOKEN_WORDS = {
    "ARROW": "'->'",
    "LPAR": "'('",
    "RPAR": "')'",
    "COMMA": "','",
    "SEMICOLON": "';'",
    "NAME": "a name",
    "NUMBER": "a number",
    "TEXREF": "a texture Rep:name or Fit>name",
    "STRING": "a quoted file name",
    "USE": "'use'",
    "AS": "'as'",
    "$END": "the end of the file",
    "OROR": "'||'",
    "ANDAND": "'&&'",
    "COMPARE": "a comparison",
    "ADDOP": "'+' or '-'",
    "MULOP": "'*', '/' or '%'",
    "NOT": "'!'",
}


@dataclass(frozen=True)
class Arg:
    """One argument as written: kind is 'number', 'name', 'texref' or 'expr' (an expression with
    operators, in `expr`; names and numbers have theirs too, for conditions)."""

    kind: str
    text: str
    location: Location
    expr: Expr | None = None

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
    params: tuple[str, ...] = ()  # Floor(i)->...: the names its conditions may read


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
    return Lark(
        _LARK_GRAMMAR, parser="lalr", propagate_positions=True, maybe_placeholders=False, start=["start", "expr"]
    )


def _expr(path: str, node) -> Expr:
    if isinstance(node, Token):
        raise AssertionError("expressions are trees")
    if node.data in ("number", "name", "texref"):
        token = node.children[0]
        if node.data == "number":
            return Expr("num", _loc(path, token), value=float(token))
        return Expr("var", _loc(path, token), name=str(token))
    if node.data == "call":
        name, *args = node.children
        return Expr("call", _loc(path, name), name=str(name), args=tuple(_expr(path, a) for a in args))
    if node.data == "binary":
        left, op, right = node.children
        return Expr(str(op), _loc(path, op), args=(_expr(path, left), _expr(path, right)))
    op, operand = node.children
    return Expr("not" if node.data == "not_" else "neg", _loc(path, op), args=(_expr(path, operand),))


def _arg(path: str, node) -> Arg:
    if node.data in ("number", "name", "texref"):
        token = node.children[0]
        return Arg(node.data, str(token), _loc(path, token), _expr(path, node))
    first = node
    while not isinstance(first, Token):
        first = first.children[0]
    return Arg("expr", "an expression", _loc(path, first), _expr(path, node))


def _check_nesting(tree: Tree, path: str, text: str) -> None:
    """Raises GrammarError at the first token nested deeper than MAX_NESTING (walked without recursion)."""
    stack = [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_NESTING:
            while not isinstance(node, Token):
                node = node.children[0]
            raise GrammarError(
                [
                    Diagnostic(
                        _loc(path, node),
                        f"arguments nest more than {MAX_NESTING} levels deep",
                        "write the inner part as a rule of its own",
                    )
                ],
                {path: text},
            )
        stack.extend((child, depth + 1) for child in node.children if isinstance(child, Tree))


def parse_expression(text: str, where: Location) -> Expr:
    """A built-in expression's text (split.first, ...), located where its name was written."""
    tree = _parser().parse(text, start="expr")
    _check_nesting(tree, where.path, text)
    located = _expr(where.path, tree)
    return _relocate(located, where)


def _relocate(expr: Expr, where: Location) -> Expr:
    return Expr(expr.op, where, expr.value, expr.name, tuple(_relocate(a, where) for a in expr.args))


def _loc(path: str, token: Token) -> Location:
    return Location(path, token.line, token.column, max(len(str(token)), 1))


def parse_text(text: str, path: str) -> SourceFile:
    """Parses one file's text; syntax errors raise GrammarError naming file:line:col."""
    try:
        tree = _parser().parse(text, start="start")
    except UnexpectedInput as exc:
        raise GrammarError([_syntax_diagnostic(exc, text, path)], {path: text}) from None
    _check_nesting(tree, path, text)
    rules, uses = [], []
    for node in tree.children:
        if node.data == "use":
            _, file_tok, _, ns_tok = node.children
            uses.append(UseDef(str(file_tok)[1:-1], str(ns_tok), _loc(path, ns_tok)))
            continue
        name_tok, *rest = node.children
        params = ()
        if rest and isinstance(rest[0], Tree):
            params = tuple(str(t) for t in rest.pop(0).children)
        arrow_tok, op_tok, *arg_nodes = rest
        if node.data == "alias":  # A->B: the operator is the arrow, its one argument the target
            args = (Arg("name", str(op_tok), _loc(path, op_tok)),)
            rules.append(RuleDef(str(name_tok), ALIAS, args, _loc(path, name_tok), _loc(path, arrow_tok), params))
            continue
        args = tuple(_arg(path, a) for a in arg_nodes)
        rules.append(RuleDef(str(name_tok), str(op_tok), args, _loc(path, name_tok), _loc(path, op_tok), params))
    return SourceFile(path, tuple(rules), tuple(uses))


def _syntax_diagnostic(exc: UnexpectedInput, text: str, path: str) -> Diagnostic:
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        lines = text.rstrip().split("\n") or [""]
        loc = Location(path, len(lines), len(lines[-1]) + 1)
        expected = _expected_words(getattr(exc, "expected", ()))
        return Diagnostic(
            loc, f"the file ends in the middle of a rule; expected {expected}", "close the argument list with ')'"
        )
    if isinstance(exc, UnexpectedCharacters):
        char = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else "?"
        loc = Location(path, exc.line, exc.column)
        hint = "rules look like Name->Operator(arg, ...); '#' starts a comment"
        if char in ":>":
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


_OPERATOR_TOKENS = {"OROR", "ANDAND", "COMPARE", "ADDOP", "MULOP"}


def _expected_words(expected) -> str:
    # After an argument an operator could always continue it: name only what ends it.
    expected = set(expected) - _OPERATOR_TOKENS or set(expected)
    words = sorted({_TOKEN_WORDS.get(e, e) for e in expected})
    return " or ".join(words) if words else "something else"
