"""Translates the facade subset of CityEngine CGA into cityshade's grammar language.

Translated: rules, `attr`/`const` values (evaluated and written in as numbers: attributes become
fixed parameters), `split(x|y)` with absolute, floating (`~`) and relative (`'`) sizes, repeats
`{...}*` (alone: Repeat; beside other parts: a Tile), `case`/`else` (Case, with split.index,
split.total, scope.sx/sy), rule parameters (`Floor(i)`, `Floor(split.index)`), `%` choices
(Rand), `rand(a, b)` sizes, `color(...)` ("#rrggbb", "#rgb", CSS names, constant r, g, b: a
Color layer under the successors, labelled by the rule's name, or a Tint of a texture that
follows it), `texture`/`i` (a library tile chosen by the file's name), `NIL`.
Everything else (comp, extrude, roofs, transformations, occlusion queries, string values...)
is listed by line with what was done instead.
"""

from __future__ import annotations

import ast
import operator
import re
from dataclasses import dataclass, field

from PIL import ImageColor

from ..errors import UsageError
from ._limits import MAX_PARAMS

_TOKEN = re.compile(
    r"""
    (?P<ws>\s+) | (?P<comment>//[^\n]*|\#[^\n]*|/\*.*?\*/) | (?P<arrow>-->)
  | (?P<num>\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+) | (?P<str>"[^"\n]*"|'[^'\n]*'(?=\s*[,)]))
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*\.?)
  | (?P<op>==|!=|<=|>=|&&|\|\||[-+*/%<>!~'(){}\[\]|:,=@^.;])
  | (?P<bad>.)""",
    re.VERBOSE | re.DOTALL,
)

# CGA operations that change 3D geometry or the scope: dropped (the facade is the scope).
_DROPPED = {
    "extrude",
    "s",
    "t",
    "r",
    "center",
    "alignScopeToAxes",
    "alignScopeToGeometry",
    "rotateScope",
    "setPivot",
    "mirror",
    "mirrorScope",
    "reverseNormals",
    "cleanupGeometry",
    "roofGable",
    "roofHip",
    "roofShed",
    "roofPyramid",
    "taper",
    "offset",
    "innerRectangle",
    "setback",
    "shapeO",
    "shapeU",
    "shapeL",
    "footprint",
    "convexify",
    "deleteUV",
    "normalizeUV",
    "scaleUV",
    "rotateUV",
    "tileUV",
    "projectUV",
    "setupProjection",
    "set",
    "print",
    "report",
    "label",
    "comp",
    "envelope",
    "translateUV",
    "primitiveCube",
    "primitiveQuad",
    "primitiveCylinder",
    "primitiveSphere",
    "resetGeometry",
    "trim",
    "insertAlongUV",
    "scatter",
    "setNormals",
    "softenNormals",
    "modify",
    "copy",
}
_QUERIES = ("inside", "overlaps", "touches", "occlusion")
# Texture and asset names -> library tiles, first match wins.
_TILES = (
    ("door", "Fit>door1"),
    ("shop", "Fit>shop_front1"),
    ("balcon", "Fit>balcony_rail1"),
    ("rail", "Fit>balcony_rail1"),
    ("sill", "Fit>sill"),
    ("cornice", "Fit>cornice1"),
    ("ledge", "Fit>cornice2"),
    ("awning", "Fit>awning"),
    ("glass", "Fit>glass"),
    ("win", "Fit>window1"),
    ("roof", "Rep:roof_tiles"),
    ("brick", "Rep:wall1"),
    ("stone", "Rep:stone_ashlar"),
    ("concrete", "Rep:concrete"),
    ("stucco", "Rep:plaster_white"),
    ("plaster", "Rep:plaster_white"),
    ("wall", "Rep:wall2"),
)
# Rule names -> the label of the colours they set (first match wins; otherwise wall).
_LABELS = (
    ("window", "window"),
    ("glass", "window"),
    ("door", "door"),
    ("entr", "door"),
    ("balcon", "balcony"),
    ("rail", "balcony"),
    ("shop", "shop"),
    ("roof", "roof"),
    ("cornice", "cornice"),
    ("ledge", "cornice"),
    ("sill", "cornice"),
)
_CONDITION_NAMES = {"split.index", "split.total", "scope.sx", "scope.sy"}
# Tokens of one value (attr, const, size, colour) that are evaluated. Real values are a number or a short sum; a
# longer one is not (Python's parser needs memory and stack per nested operator: 100,000 unary
# minuses exhaust them), and 256 keeps the recursive evaluation far from the recursion limit.
MAX_VALUE_TOKENS = 256


class CgaError(UsageError):
    """The file cannot be translated at all (nothing is written): exit code 2."""


@dataclass
class Note:
    line: int
    what: str
    instead: str

    def format(self, path: str) -> str:
        return f"{path}:{self.line}: {self.what}: {self.instead}"


@dataclass
class Translation:
    text: str
    notes: list[Note] = field(default_factory=list)


@dataclass(frozen=True)
class _Tok:
    kind: str
    text: str
    line: int


def _tokens(text: str) -> list[_Tok]:
    out, line = [], 1
    for match in _TOKEN.finditer(text):
        kind, value = match.lastgroup, match.group()
        if kind not in ("ws", "comment"):
            if kind == "name" and value.endswith(".") and len(value) > 1:  # `Leaf.`: a leaf shape
                out.append(_Tok("name", value[:-1], line))
                kind, value = "op", "."
            out.append(_Tok(kind, value, line))
        line += value.count("\n")
    return out


def _partner(tokens: list[_Tok], i: int, opening: str, closing: str) -> int:
    """The index of the bracket closing the one at i (len(tokens) if it is never closed)."""
    depth = 0
    for k in range(i, len(tokens)):
        if tokens[k].kind == "op":
            depth += (tokens[k].text == opening) - (tokens[k].text == closing)
            if depth == 0:
                return k
    return len(tokens)


def _single_layer(op: str) -> str | None:
    """X for the operator text Layer(X) of one successor (X may carry arguments), else None."""
    if not op.startswith("Layer(") or not op.endswith(")"):
        return None
    inner, depth = op[len("Layer(") : -1], 0
    for char in inner:
        depth += (char == "(") - (char == ")")
        if char == "," and depth == 0:
            return None
    return inner


def _labelled(color: str, rule: str) -> str:
    """Color(r, g, b) closed with the label its rule's name suggests (none for a wall)."""
    lowered = rule.lower()
    label = next((label for key, label in _LABELS if key in lowered), None)
    return f"{color}, {label})" if label else f"{color})"


def _number(value: float) -> str:
    """A number as the grammar is written: at most 6 decimals, no exponent (0.9, not 0.8999999999999999)."""
    return f"{value:.6f}".rstrip("0").rstrip(".") or "0"


def _arguments(tokens: list[_Tok]) -> list[list[_Tok]]:
    """The comma-separated arguments of a call, each a token list (commas inside brackets stay)."""
    parts, depth, start = [], 0, 0
    for k, t in enumerate(tokens):
        if t.kind == "op" and t.text in "([{":
            depth += 1
        elif t.kind == "op" and t.text in ")]}":
            depth -= 1
        elif depth == 0 and t.kind == "op" and t.text == ",":
            parts.append(tokens[start:k])
            start = k + 1
    return parts + [tokens[start:]] if tokens else parts


_BINARY = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv, "%": operator.mod}


def _constant(node, values: dict):
    """A number from a Python-parsed expression over attrs and consts, or None."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and isinstance(values.get(node.id), float):
        return values[node.id]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        inner = _constant(node.operand, values)
        return None if inner is None else -inner
    if isinstance(node, ast.BinOp) and type(node.op) in (ast.Add, ast.Sub, ast.Mult, ast.Div):
        left, right = _constant(node.left, values), _constant(node.right, values)
        symbol = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}[type(node.op)]
        if left is None or right is None or (symbol == "/" and right == 0):
            return None
        return _BINARY[symbol](left, right)
    return None


class _Importer:
    def __init__(self, text: str):
        self.toks = _tokens(text)
        self.pos = 0
        self.values: dict[str, object] = {}
        self.rules: dict[str, str] = {}  # name -> operator text
        self.order: list[str] = []
        self.notes: list[Note] = []
        self.aux = 0
        self.referenced: dict[str, int] = {}  # successor -> first line naming it
        self.params: dict[str, tuple[str, ...]] = {}  # rule -> its parameters
        self.current: tuple[str, ...] = ()  # the parameters of the rule being translated
        self.arity: dict[str, int] = {}  # successor -> arguments it was first given

    # ---------------------------------------------------------------- tokens
    def peek(self, offset: int = 0) -> _Tok | None:
        i = self.pos + offset
        return self.toks[i] if i < len(self.toks) else None

    def next(self) -> _Tok:
        tok = self.toks[self.pos]
        self.pos += 1
        return tok

    def at(self, text: str, offset: int = 0) -> bool:
        tok = self.peek(offset)
        return tok is not None and tok.text == text and tok.kind in ("op", "arrow", "name")

    def note(self, line: int, what: str, instead: str):
        self.notes.append(Note(line, what, instead))

    def balanced(self, opening: str, closing: str) -> list[_Tok]:
        """The tokens between a bracket at the cursor and its partner (both consumed)."""
        self.next()
        depth, out = 1, []
        while self.peek() is not None:
            tok = self.next()
            if tok.kind == "op" and tok.text == opening:
                depth += 1
            elif tok.kind == "op" and tok.text == closing:
                depth -= 1
                if depth == 0:
                    return out
            out.append(tok)
        raise CgaError(f"'{opening}' is never closed")

    def rule_starts(self) -> bool:
        """A rule head at the cursor: Name --> or Name(params) -->."""
        tok = self.peek()
        if tok is None or tok.kind != "name":
            return False
        if self.at("-->", 1):
            return True
        if self.at("(", 1):
            depth, i = 0, 1
            while (t := self.peek(i)) is not None:
                depth += (t.text == "(") - (t.text == ")") if t.kind == "op" else 0
                i += 1
                if depth == 0:
                    return self.at("-->", i)
        return False

    # ---------------------------------------------------------------- file
    def run(self) -> Translation:
        while self.peek() is not None:
            tok = self.peek()
            if tok.text in ("attr", "const") and tok.kind == "name":
                self.definition()
            elif tok.text == "@":
                self.next()
                self.next()
                if self.at("("):
                    self.balanced("(", ")")
            elif tok.text in ("version", "import") and tok.kind == "name":
                self.next()
                line = tok.line
                while self.peek() is not None and self.peek().line == line:
                    self.next()
                if tok.text == "import":
                    self.note(line, "import of another rule file", "not followed; its rules are missing")
            elif self.rule_starts():
                self.rule()
            elif tok.kind == "name" and self.at("=", 1):  # a bare constant (old CGA)
                self.definition(bare=True)
            else:
                self.note(tok.line, f"unexpected {tok.text!r}", "skipped")
                self.next()
        if not self.order:
            raise CgaError("no rules found")
        return Translation(self.write(), self.notes)

    def definition(self, bare: bool = False):
        if not bare:
            self.next()
        name = self.next()
        self.next()  # '='
        line = name.line
        tokens = []
        while self.peek() is not None and not (
            self.peek().line != line and (self.rule_starts() or self.peek().text in ("attr", "const", "@"))
        ):
            tokens.append(self.next())
        self.values[name.text] = self.value(tokens)

    def value(self, tokens: list[_Tok]):
        if len(tokens) == 1 and tokens[0].kind == "str":
            return tokens[0].text[1:-1]
        if len(tokens) > MAX_VALUE_TOKENS:
            self.note(tokens[0].line, f"a value of {len(tokens)} tokens", "not evaluated; it is unknown")
            return None
        text = " ".join(t.text for t in tokens)
        try:
            return _constant(ast.parse(text, mode="eval").body, self.values)
        except SyntaxError:
            return None

    # ---------------------------------------------------------------- rules
    def rule(self):
        head = self.next()
        params: tuple[str, ...] = ()
        if self.at("("):
            params = tuple(t.text for t in self.balanced("(", ")") if t.kind == "name")
            if len(params) > MAX_PARAMS:
                self.note(
                    head.line,
                    f"{len(params)} parameters of {head.text}",
                    f"only the first {MAX_PARAMS} are kept (the GPU's limit)",
                )
                params = params[:MAX_PARAMS]
        self.next()  # -->
        body = self.body_tokens()
        name = self.rule_name(head.text)
        if name in self.rules:
            self.note(head.line, f"a second rule {head.text}", "the first one is kept")
            return
        self.order.append(name)  # before its helper rules: the first rule stays the start rule
        self.rules[name] = "Skip(0)"
        self.params[name] = params
        self.current = params
        self.rules[name] = self.translate_body(body, head.line, name)

    def rule_name(self, name: str) -> str:
        return name.replace(".", "_")

    def body_tokens(self) -> list[_Tok]:
        out = []
        while (
            self.peek() is not None
            and not self.rule_starts()
            and not (self.peek().kind == "name" and self.peek().text in ("attr", "const") or self.at("@"))
        ):
            out.append(self.next())
        return out

    def fresh(self, base: str, text: str) -> str:
        self.aux += 1
        name = f"{base}_{self.aux}"
        self.rules[name] = text
        self.order.append(name)
        return name

    def translate_body(self, body: list[_Tok], line: int, name: str) -> str:
        """The operator text of a rule body: a case/percentage choice or a sequence of operations."""
        if body and body[0].text == "case":
            return self.choice(body, line, name, "case")
        if len(body) > 1 and body[0].kind == "num" and body[1].text == "%":
            return self.choice(body, line, name, "%")
        return self.sequence(body, line, name)

    def branches(self, body: list[_Tok], keyword: str):
        """(head tokens, branch tokens) per branch of a case or % choice; else has head None."""
        branches, i = [], 0
        while i < len(body):
            if body[i].text == "else":
                branches.append((None, body[i + 2 :]))
                break
            j = i + 1
            depth = 0
            while j < len(body) and not (depth == 0 and body[j].text == ":" and body[j].kind == "op"):
                depth += (body[j].text in "([{") - (body[j].text in ")]}") if body[j].kind == "op" else 0
                j += 1
            head = body[i + 1 : j] if keyword == "case" else body[i : j - 1]
            k = j + 1
            depth = 0
            while k < len(body):
                t = body[k]
                if depth == 0 and (
                    t.text in ("case", "else")
                    or (keyword == "%" and t.kind == "num" and k + 1 < len(body) and body[k + 1].text == "%")
                ):
                    break
                depth += (t.text in "([{") - (t.text in ")]}") if t.kind == "op" else 0
                k += 1
            branches.append((head, body[j + 1 : k]))
            i = k
        return branches

    def choice(self, body, line, name, keyword) -> str:
        branches = self.branches(body, keyword)
        args, fallback = [], None
        weights = []
        for head, tokens in branches:
            target = self.target(tokens, tokens[0].line if tokens else line, name)
            if head is None:
                fallback = target
            elif keyword == "case":
                args.append(f"{self.condition(head, head[0].line if head else line)}, {target}")
            else:
                weights.append((self.value(head) or 0.0, target))
        if fallback is None:
            fallback = self.skip()
        if keyword == "case":
            return f"Case({', '.join(args)}, {fallback})"
        total = sum(w for w, _ in weights)
        if total < 100 or fallback != "NIL":
            weights.append((max(100 - total, 0.0), fallback))
        weights = [(w, t) for w, t in weights if w > 0]
        scale = sum(w for w, _ in weights)
        parts = [f"{w / scale:.4f}, {t}" for w, t in weights]
        # the weights must sum to 1 in the 4 written decimals: the last takes the rounding
        last = 1 - sum(round(w / scale, 4) for w, _ in weights[:-1])
        parts[-1] = f"{last:.4f}, {weights[-1][1]}"
        return f"Rand(0, {', '.join(parts)})"

    def skip(self) -> str:
        """CGA's NIL, which deletes the shape: nothing is drawn there, not even the colour a rule above
        set (the translation puts it in the layer below, which Skip(1) skips too); a leaf without a
        rule, in contrast, shows that colour (Skip(0))."""
        self.rules.setdefault("NIL", "Skip(1)")  # NIL is CGA's keyword: no CGA rule has its name
        if "NIL" not in self.order:
            self.order.append("NIL")
        return "NIL"

    def condition(self, tokens: list[_Tok], line: int) -> str:
        """A CGA expression in cityshade's condition language ('0', and a note, if it cannot be)."""
        words = []
        for tok in tokens:
            value = self.values.get(tok.text) if tok.kind == "name" else None
            if tok.kind == "name" and (tok.text in _CONDITION_NAMES or tok.text in self.current):
                words.append(tok.text)
            elif tok.kind == "name" and tok.text in ("true", "false"):
                words.append("1" if tok.text == "true" else "0")
            elif isinstance(value, float):
                words.append(_number(value))
            elif tok.kind in ("num",) or (tok.kind == "op" and tok.text not in ("'", "~", "{", "}", "[", "]")):
                words.append(tok.text)
            else:
                self.note(
                    line,
                    f"condition {' '.join(t.text for t in tokens)!r} uses {tok.text}",
                    "the condition is taken as false",
                )
                return "0"
        text = " ".join(words)
        from ._diagnostics import Location
        from ._syntax import parse_expression  # the cityshade parser decides what it reads

        try:
            parse_expression(text, Location("<cga>", line, 1))
        except Exception:  # lark's errors: anything it cannot read is reported, never raised
            self.note(line, f"condition {text!r}", "not understood; taken as false")
            return "0"
        return text

    def sequence(self, tokens: list[_Tok], line: int, name: str) -> str:
        """Operations then successors -> one operator (Layers for colours, textures and several successors)."""
        layers: list[str] = []  # bottom first
        i = 0
        while i < len(tokens):
            tok = tokens[i]
            if tok.kind == "name" and i + 1 < len(tokens) and tokens[i + 1].text == "(":
                j = _partner(tokens, i + 1, "(", ")")
                args = tokens[i + 2 : j]
                i = j + 1
                if tok.text == "split" and i < len(tokens) and tokens[i].text == "{":
                    k = _partner(tokens, i, "{", "}")
                    parts = tokens[i + 1 : k]
                    if k >= len(tokens):
                        self.note(tok.line, "split(...){ is never closed", "its parts are read to the end of the rule")
                    i = k + 1
                    repeat = i < len(tokens) and tokens[i].text == "*"
                    i += repeat
                    layers.append(("op", self.split(args, parts, repeat, tok.line, name)))
                elif tok.text == "color":
                    layers.append(("op", self.color(args, tok.line, name)))
                elif tok.text in ("texture", "i"):
                    layers.append(("op", self.tile(args, tok.line, tok.text)))
                elif tok.text in _DROPPED or any(tok.text.startswith(q) for q in _QUERIES):
                    what = "comp" if tok.text == "comp" else tok.text
                    if tok.text == "comp" and i < len(tokens) and tokens[i].text == "{":
                        layers.append(("rule", self.comp(tokens, i, line, name)))
                        i = self.skip_braces(tokens, i)
                    else:
                        self.note(tok.line, f"{what}(...)", "dropped: cityshade draws one flat facade scope")
                else:  # a successor with arguments: Floor(split.index)
                    layers.append(("rule", self.successor(tok, args)))
            elif tok.kind == "name" and tok.text == "NIL":
                layers.append(("rule", self.skip()))
                i += 1
            elif tok.kind == "name":
                layers.append(("rule", self.successor(tok)))
                i += 1
            elif tok.text in ("[", "]", ".", ";"):
                if tok.text == "[":
                    self.note(tok.line, "push/pop [ ]", "the branch is drawn as a layer of the same scope")
                i += 1
            else:
                self.note(tok.line, f"unexpected {tok.text!r}", "skipped")
                i += 1
        layers = self.tint_textures(layers, name)
        if not layers:
            return "Skip(0)"
        if len(layers) == 1:  # one operation is the rule itself; one successor makes an alias
            kind, text = layers[0]
            return text if kind == "op" else f"Layer({text})"
        names = [text if kind == "rule" else self.fresh(name, text) for kind, text in layers]
        return f"Layer({', '.join(names)})"

    def tint_textures(self, layers: list[tuple[str, str]], name: str) -> list[tuple[str, str]]:
        """color(...) then texture(...) in one rule: CGA multiplies the texture by the colour, so the
        pair becomes Tint(r, g, b, the texture) instead of two layers."""
        out: list[tuple[str, str]] = []
        for kind, text in layers:
            previous = out[-1] if out else None
            if (
                kind == "op"
                and text.startswith("Mat(")
                and previous is not None
                and previous[0] == "op"
                and previous[1].startswith("Color(")
            ):
                rgb = ", ".join(previous[1][len("Color(") : -1].split(", ")[:3])  # a Tint has no label
                out[-1] = ("op", f"Tint({rgb}, {self.fresh(name, text)})")
            else:
                out.append((kind, text))
        return out

    def target(self, tokens: list[_Tok], line: int, name: str) -> str:
        """The rule a split part or a branch goes to: a successor itself, or a new helper rule."""
        op = self.sequence(tokens, line, name)
        return _single_layer(op) or self.fresh(name, op)

    def successor(self, tok: _Tok, args: list[_Tok] | None = None) -> str:
        name = self.rule_name(tok.text)
        self.referenced.setdefault(name, tok.line)
        if not args:
            self.arity.setdefault(name, 0)
            return name
        values = [self.condition(part, tok.line) for part in _arguments(args)]
        self.arity.setdefault(name, len(values))
        return f"{name}({', '.join(values[:MAX_PARAMS])})"

    def skip_braces(self, tokens, i):
        """The index after the brace group that opens at i."""
        return _partner(tokens, i, "{", "}") + 1

    def comp(self, tokens, i, line, name) -> str:
        """comp(f){ front: A | side: B | top: R }: the facade is the front's (or sides') rule."""
        inner = tokens[i + 1 : self.skip_braces(tokens, i) - 1]
        chosen = None
        for selector in ("front", "side", "street.front", "all"):
            for k, tok in enumerate(inner[:-2]):
                if tok.text == selector and inner[k + 1].text == ":" and inner[k + 2].kind == "name":
                    chosen = chosen or self.rule_name(inner[k + 2].text)
        self.note(
            tokens[i].line,
            "comp(f){...}",
            f"only the facade is kept: {chosen or 'none found'}; roofs and other faces are dropped",
        )
        if chosen is None:
            return self.skip()
        self.referenced.setdefault(chosen, tokens[i].line)
        return chosen

    def size(self, tokens: list[_Tok], line: int) -> tuple[str, str]:
        """(policy, size text) of a split part's size."""
        policy = "Abs"
        if tokens and tokens[0].text == "~":
            policy, tokens = "Rel", tokens[1:]
        elif tokens and tokens[0].text == "'":
            policy, tokens = "Frac", tokens[1:]
        if len(tokens) >= 4 and tokens[0].text == "rand" and tokens[1].text == "(":
            inner = tokens[2:-1]
            comma = [k for k, t in enumerate(inner) if t.text == ","]
            if comma:
                low, high = self.value(inner[: comma[0]]), self.value(inner[comma[0] + 1 :])
                if low is not None and high is not None and 0 < low <= high:
                    return policy, f"rand({_number(low)}, {_number(high)})"
        value = self.value(tokens)
        if not isinstance(value, float) or value <= 0:
            self.note(line, f"size {' '.join(t.text for t in tokens)!r}", "not a positive number here; 1 is used")
            value = 1.0
        return policy, _number(value)

    def split_parts(self, tokens: list[_Tok]):
        """(size tokens, successor tokens, repeated group tokens or None) per part of a split."""
        parts, i = [], 0
        while i < len(tokens):
            if tokens[i].text == "{":
                end = self.skip_braces(tokens, i)
                repeated = end < len(tokens) and tokens[end].text == "*"
                parts.append((None, None, tokens[i + 1 : end - 1], repeated))
                i = end + repeated
            else:
                j, depth = i, 0
                while j < len(tokens) and not (depth == 0 and tokens[j].text == "|"):
                    depth += (tokens[j].text in "([{") - (tokens[j].text in ")]}") if tokens[j].kind == "op" else 0
                    j += 1
                part = tokens[i:j]
                colon = next((k for k, t in enumerate(part) if t.text == ":"), None)
                if colon is not None:
                    parts.append((part[:colon], part[colon + 1 :], None, False))
                i = j
            if i < len(tokens) and tokens[i].text == "|":
                i += 1
        return parts

    def split(self, args, parts_tokens, repeat, line, name) -> str:
        axis = "X" if args and args[0].text == "x" else "Y"
        if args and args[0].text not in ("x", "y"):
            self.note(line, f"split({args[0].text})", "a facade splits along x or y: taken as y")
        parts = self.split_parts(parts_tokens)
        if repeat and len(parts) == 1 and parts[0][2] is None:
            sizes, successor = parts[0][0], parts[0][1]
            policy, value = self.size(sizes, line)
            if policy == "Abs":
                self.note(
                    line,
                    "an absolute repeat {size: X}*",
                    "repeated the nearest whole number of times, "
                    "stretched to fill the scope (CGA leaves the remainder)",
                )
            return f"Repeat{axis}({value}, {self.target(successor, line, name)})"
        if repeat:
            parts = [(None, None, parts_tokens, True)]
        if not parts:
            self.note(line, "a split without parts", "drawn transparent")
            return "Skip(0)"
        out, fractions, tiles = [], [], 0
        for sizes, successor, group, _repeated in parts:
            if group is not None:
                inner = self.split_parts(group)
                tiles += 1
                if tiles > 1:
                    self.note(line, "a second repeated group in one split", "drawn once, not repeated")
                if len(inner) == 1 and inner[0][2] is None:
                    _, value = self.size(inner[0][0], line)
                    if value.startswith("rand("):
                        low, high = (float(x) for x in value[5:-1].split(","))
                        value = _number((low + high) / 2)
                        self.note(line, "a repeated part of rand size", f"a fixed size {value}, the middle")
                    target = self.target(inner[0][1], line, name)
                else:
                    total = sum(
                        float(self.size(p[0], line)[1].split("(")[-1].split(",")[0].rstrip(")"))
                        for p in inner
                        if p[0] is not None
                    )
                    value = _number(total if total > 0 else 1.0)
                    target = self.fresh(name, self.split(args, group, False, line, name))
                    self.note(
                        line,
                        "a repeated group of several parts",
                        "one Tile of their summed size holding a Split of the parts",
                    )
                out.append(("Tile" if tiles == 1 else "Rel", value, target))
                continue
            policy, value = self.size(sizes, line)
            target = self.target(successor, line, name)
            if policy == "Frac":
                fractions.append(len(out))
            out.append((policy, value, target))
        if fractions:
            self.note(
                line,
                "relative sizes ('r)",
                "written as floating (Rel) parts: exact when they sum to 1 "
                "and stand alone, otherwise they share the scope with the floating parts",
            )
        text = ", ".join(f"{'Rel' if p == 'Frac' else p}, {v}, {t}" for p, v, t in out)
        return f"Split{axis}({text})"

    def color(self, args, line, name) -> str:
        """color("#rrggbb"), color("#rgb"), a CSS colour name (color("lightblue")) or color(r, g, b)
        with constant channels in [0, 1]; anything else is grey (listed). The colour is labelled by
        its rule's name (a Window's colour is a window in the label image), else wall."""
        shown = f"color({' '.join(a.text for a in args)})"
        parts = _arguments(args)
        if len(parts) == 3:
            rgb = [self.value(part) for part in parts]
            if all(isinstance(c, float) and 0 <= c <= 1 for c in rgb):
                return _labelled(f"Color({rgb[0]:.3f}, {rgb[1]:.3f}, {rgb[2]:.3f}", name)
            self.note(line, shown, "channels that are not constants in [0, 1]; grey is used")
            return "Color(0.5, 0.5, 0.5)"
        text = self.value(args) if args else None
        if len(args) == 1 and args[0].kind == "name":  # a const or attr holding the colour
            text = self.values.get(args[0].text)
        try:
            if not isinstance(text, str):
                raise ValueError(text)
            r, g, b = (c / 255 for c in ImageColor.getrgb(text.strip())[:3])
        except ValueError:
            self.note(line, shown, "not a colour (#rrggbb, #rgb or a CSS colour name); grey is used")
            return "Color(0.5, 0.5, 0.5)"
        return _labelled(f"Color({r:.3f}, {g:.3f}, {b:.3f}", name)

    def tile(self, args, line, what) -> str:
        name = args[0].text.strip("\"'") if args else ""
        if args and args[0].kind == "name" and isinstance(self.values.get(args[0].text), str):
            name = self.values[args[0].text]
        lowered = name.lower()
        tile = next((t for key, t in _TILES if key in lowered), "Rep:wall1")
        kind = "3D asset insert" if what == "i" else "texture"
        self.note(line, f"{kind} {name!r}", f"drawn as the library tile {tile}")
        if tile.startswith("Rep:"):
            return f"Mat(Color, {tile}, 0, 0, 0.5, 0.5)"
        return f"Mat(Color, {tile}, 0, 0, 1, 1)"

    # ---------------------------------------------------------------- output
    def write(self) -> str:
        for name, line in sorted(self.referenced.items(), key=lambda item: item[1]):
            if name not in self.rules:
                self.note(line, f"shape {name} has no rule (a leaf)", "drawn transparent: Skip(0)")
                self.rules[name] = "Skip(0)"
                self.params[name] = tuple(f"p{k}" for k in range(min(self.arity.get(name, 0), MAX_PARAMS)))
                self.order.append(name)
        lines = []
        for name in self.order:
            op = self.rules[name]
            op = _single_layer(op) or op  # one successor: an alias
            params = self.params.get(name, ())
            lines.append(f"{name}({', '.join(params)})->{op}" if params else f"{name}->{op}")
        return "\n".join(lines) + "\n"


def translate(text: str, path: str = "<cga>") -> Translation:
    """Translates CGA text; raises CgaError (naming path:line) when it cannot be read."""
    importer = _Importer(text)
    try:
        return importer.run()
    except CgaError as exc:
        line = importer.peek().line if importer.peek() else (importer.toks[-1].line if importer.toks else 1)
        raise CgaError(f"{path}:{line}: error: {exc}; nothing was written") from None
    except (IndexError, ValueError, KeyError, RecursionError):  # input this subset cannot read
        tok = importer.peek() or (importer.toks[-1] if importer.toks else None)
        where = f"{path}:{tok.line}" if tok else path
        shown = tok.text[:40] if tok else ""
        raise CgaError(
            f"{where}: error: cannot read the CGA at {shown!r} (the importer knows the facade "
            "subset: rules, attr, split, repeat, case, %, color, texture, i); nothing was written"
        ) from None
