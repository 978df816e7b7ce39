"""Semantic checks: every rule's operator, arguments, references and limits, each error located.

The result is a `Grammar`: rules with typed argument values, ready for the compiler and the
reference evaluator.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..assets import LABELS
from ..errors import CityshadeError
from . import _limits as limits
from ._diagnostics import Diagnostic, GrammarError, shorten, suggest
from ._expressions import Expr, check_expr, program, stack_depth
from ._loader import SourceGrammar, SourceRule
from ._operators import ALIAS, OPERATORS, POLICIES, ROUNDINGS, TILE, USAGES, Kind
from ._syntax import Arg


@dataclass(frozen=True)
class TexRef:
    """A texture argument: tile index and mode (fit to the scope, or tiled). tile -1 = constant."""

    tile: int
    fit: bool

    @property
    def code(self) -> int:
        """The paper's m1: 0 constant, > 0 fit, < 0 tiled; tile index + 1."""
        if self.tile < 0:
            return 0
        return self.tile + 1 if self.fit else -(self.tile + 1)


@dataclass(frozen=True)
class RandomSize:
    """rand(low, high): a size drawn per scope (stable for a facade and seed), in metres."""

    low: float
    high: float


@dataclass(frozen=True)
class Bound:
    """A reference with arguments, Floor(split.index): the values are set, then `name` runs."""

    name: str
    args: tuple


@dataclass(frozen=True)
class Rule:
    name: str
    operator: str
    values: tuple  # per argument: rule name (str), float, int or TexRef
    source: SourceRule

    @property
    def children(self) -> tuple[str, ...]:
        kinds = _kinds(self.operator, len(self.values))
        return tuple(getattr(v, "name", v) for v, k in zip(self.values, kinds) if k is Kind.RULE)

    @property
    def binds(self) -> bool:
        """Some reference passes arguments (one more operator step on its path)."""
        return any(isinstance(v, Bound) for v in self.values)


@dataclass
class Grammar:
    """A checked grammar: rules by full name, in definition order; `start` is the default rule."""

    rules: dict[str, Rule]
    start: str
    sources: dict[str, str] = field(default_factory=dict)

    def rule(self, name: str | None) -> Rule:
        name = name or self.start
        if name not in self.rules:
            hint = suggest(name, self.rules, "rule")
            raise CityshadeError(f"no rule named '{name}'" + (f"; {hint}" if hint else ""))
        return self.rules[name]


def _kinds(operator: str, count: int) -> list[Kind]:
    sig = OPERATORS[operator]
    kinds = list(sig.head) + list(sig.optional)
    while len(kinds) < count - len(sig.tail) and sig.group:
        kinds.extend(sig.group)
    return (kinds + list(sig.tail))[:count]


def check(source: SourceGrammar, tile_names: dict[str, int]) -> Grammar:
    """Checks every rule; raises GrammarError listing all problems, or returns the typed Grammar."""
    errors: list[Diagnostic] = []
    rules: dict[str, Rule] = {}
    for name, src in source.rules.items():
        rule = _check_rule(src, source.rules, tile_names, errors)
        if rule is not None:
            rules[name] = rule
    if not errors:
        errors += _walk(rules)[1]
    if not errors:
        errors += _limit_errors(rules) + _index_errors(rules) + _overhang_errors(rules)
    if errors:
        errors.sort(key=lambda e: (e.location.path, e.location.line, e.location.column))
        raise GrammarError(errors, source.sources)
    return Grammar(rules, source.start, source.sources)


def _check_rule(src: SourceRule, names: dict[str, SourceRule], tiles: dict[str, int], errors: list) -> Rule | None:
    definition = src.definition
    op = definition.operator
    if op not in OPERATORS and src.resolve(op) in names:  # Floor(split.index) as a whole rule: an alias
        call = Arg(
            "expr",
            "a reference",
            definition.operator_location,
            Expr("call", definition.operator_location, name=op, args=tuple(a.expr for a in definition.args)),
        )
        target = _value(call, Kind.RULE, src, names, tiles, errors, op)
        return None if target is None else Rule(src.name, ALIAS, (target,), src)
    if op not in OPERATORS:
        errors.append(
            Diagnostic(
                definition.operator_location,
                f"unknown operator '{op}'",
                suggest(op, OPERATORS, "operator") or f"operators: {', '.join(o for o in OPERATORS if o != ALIAS)}",
            )
        )
        return None
    sig = OPERATORS[op]
    args = definition.args
    if not sig.arity_ok(len(args)):
        errors.append(
            Diagnostic(
                definition.operator_location,
                f"{op} takes ({sig.describe()}) but got {len(args)} argument{'s' * (len(args) != 1)}",
            )
        )
        return None
    count_before = len(errors)
    values = tuple(_value(arg, kind, src, names, tiles, errors, op) for arg, kind in zip(args, _kinds(op, len(args))))
    if len(errors) > count_before:
        return None
    rule = Rule(src.name, op, values, src)
    _operator_checks(rule, errors)
    return rule


def _value(arg: Arg, kind: Kind, src: SourceRule, names, tiles, errors, op):
    def fail(message: str, hint: str = ""):
        errors.append(Diagnostic(arg.location, message, hint))

    if kind is Kind.LABEL:
        if arg.kind != "name" or arg.text not in LABELS[1:]:
            return fail(
                f"{op} expects a label here, not {arg.text!r}",
                suggest(arg.text, LABELS[1:], "label") or "labels: " + ", ".join(LABELS[1:]),
            )
        return LABELS.index(arg.text)
    if kind is Kind.CONDITION:
        return check_expr(arg.expr, errors, src.definition.params)  # None, with the reason reported, if it is bad
    if kind is Kind.RULE:
        return _rule_value(arg, kind, src, names, errors, op, fail)
    if kind in (Kind.POLICY, Kind.USAGE, Kind.ROUNDING):
        table = {Kind.POLICY: POLICIES, Kind.USAGE: USAGES, Kind.ROUNDING: ROUNDINGS}[kind]
        if arg.kind != "name" or arg.text not in table:
            return fail(f"{op} expects {kind.value} here, not {arg.text!r}", suggest(arg.text, table, "constant"))
        return table[arg.text]
    if kind in (Kind.TEXTURE, Kind.MASK):
        return _texture_value(arg, kind, tiles, op, fail)
    if kind is Kind.SIZE and arg.kind == "expr" and arg.expr.op == "call":
        return _random_size(arg, op, fail)
    if arg.kind != "number":
        return fail(f"{op} expects {kind.value} here, not {arg.text!r}")
    return _number_value(arg, kind, op, fail)


def _rule_value(arg: Arg, kind: Kind, src: SourceRule, names, errors, op, fail):
    if arg.kind == "expr" and arg.expr.op == "call":
        return _bound(arg, src, names, errors, fail)
    if arg.kind != "name":
        return fail(f"{op} expects {kind.value} here, not {arg.text!r}")
    full = src.resolve(arg.text)
    if full not in names:
        local = [
            n[len(src.namespace) + 1 :] if src.namespace else n
            for n in names
            if not src.namespace or n.startswith(src.namespace + ".")
        ]
        return fail(
            f"undefined rule '{arg.text}'",
            suggest(arg.text, local, "rule") or f"define it as {arg.text}->Operator(...)",
        )
    wanted = names[full].definition.params
    if wanted:
        return fail(
            f"rule '{arg.text}' takes {len(wanted)} parameter{'s' * (len(wanted) > 1)} ({', '.join(wanted)})",
            f"write {arg.text}({', '.join(wanted)})",
        )
    return full


def _texture_value(arg: Arg, kind: Kind, tiles, op, fail):
    if arg.kind == "number" and kind is Kind.TEXTURE and arg.value == 0:
        return TexRef(-1, True)
    if arg.kind != "texref":
        return fail(f"{op} expects {kind.value} here, not {arg.text!r}")
    name = arg.text[4:]
    if name not in tiles:
        return fail(f"unknown texture '{name}'", suggest(name, tiles, "texture"))
    return TexRef(tiles[name], arg.text.startswith("Fit>"))


def _number_value(arg: Arg, kind: Kind, op, fail):
    value = arg.value
    if not abs(value) <= limits.HALF_MAX:
        return fail(
            f"{shorten(arg.text)} does not fit the GPU's 16-bit numbers",
            f"numbers of a grammar are at most {limits.HALF_MAX:g} in magnitude",
        )
    if kind is Kind.SIZE and not np.float16(value) > 0:
        return fail(f"size must be > 0, got {arg.text}", "sizes are metres; use a positive number of at least 1e-7")
    if kind is Kind.FRACTION and not 0 <= value <= 1:
        return fail(f"a colour channel is in [0, 1], got {arg.text}")
    if kind is Kind.MARGIN and not 0 <= value <= limits.MAX_OVERHANG:
        return fail(
            f"an overhang's margin is in [0, {limits.MAX_OVERHANG:g}] metres, got {arg.text}",
            "a part reaches at most that far over its neighbours",
        )
    if kind is Kind.WEIGHT and not 0 < value <= 1:
        return fail(f"weight must be in (0, 1], got {arg.text}")
    if kind is Kind.COUNT:
        if value < 0 or value != int(value):
            return fail(f"{op} expects {kind.value} here, got {arg.text}")
        return int(value)
    return value


def _bound(arg: Arg, src: SourceRule, names, errors, fail):
    call = arg.expr
    full = src.resolve(call.name)
    if full not in names:
        return fail(f"undefined rule '{call.name}'", suggest(call.name, names, "rule"))
    wanted = names[full].definition.params
    if len(call.args) != len(wanted):
        return fail(
            f"rule '{call.name}' takes {len(wanted)} argument{'s' * (len(wanted) != 1)}, got {len(call.args)}",
            f"it is defined as {call.name}({', '.join(wanted)})",
        )
    if not wanted:  # B() is B
        return full
    if len(wanted) > limits.MAX_PARAMS:
        return fail(f"rule '{call.name}' has {len(wanted)} parameters; the GPU limit is {limits.MAX_PARAMS}")
    count_before = len(errors)
    values = tuple(check_expr(a, errors, src.definition.params) for a in call.args)
    if len(errors) > count_before:
        return None
    depth = max(i + stack_depth(v) for i, v in enumerate(values))
    tokens = sum(len(program(v)) for v in values)
    if depth > limits.MAX_EXPR_STACK or tokens > limits.MAX_CASE_TOKENS:
        return fail(
            f"the arguments of {call.name}(...) need {tokens} steps and {depth} stack values; "
            f"the GPU limits are {limits.MAX_CASE_TOKENS} and {limits.MAX_EXPR_STACK}"
        )
    return Bound(full, values)


def _random_size(arg: Arg, op: str, fail):
    call = arg.expr
    if call.name != "rand":
        return fail(f"unknown function '{call.name}'", "sizes may be rand(low, high)")
    if op not in ("RepeatX", "RepeatY", "SplitX", "SplitY"):
        return fail(f"{op} takes a fixed size; rand(low, high) is for Repeat and Split sizes")
    bounds = [a.value for a in call.args if a.op == "num"]
    if len(call.args) != 2 or len(bounds) != 2:
        return fail("rand takes two numbers: rand(low, high)")
    low, high = bounds
    if not (np.float16(low) > 0 and low <= high <= limits.HALF_MAX):
        return fail(f"rand({low:g}, {high:g}) needs 0 < low <= high <= {limits.HALF_MAX:g}")
    return RandomSize(low, high)


def _operator_checks(rule: Rule, errors: list):
    definition = rule.source.definition
    if rule.operator == "Rand":
        total = sum(rule.values[1::2])
        if abs(total - 1.0) > 1e-3:
            errors.append(
                Diagnostic(
                    definition.operator_location,
                    f"Rand weights sum to {total:g}, not 1",
                    "make the weights add up to 1.0, or use RandUni for equal chances",
                )
            )
    if rule.operator in ("SplitX", "SplitY"):
        _split_checks(rule, definition, errors)
    if rule.operator in ("SplitX", "SplitY", "Rand") and len(rule.children) > limits.MAX_PARTS:
        errors.append(
            Diagnostic(
                definition.operator_location,
                f"{rule.operator} has {len(rule.children)} parts; the GPU limit is {limits.MAX_PARTS}",
                "nest two operators instead",
            )
        )
    if rule.operator == "Case":
        _case_checks(rule, definition, errors)
    if rule.operator in ("Mat", "MatAlpha"):
        _mat_checks(rule, definition, errors)


def _split_checks(rule: Rule, definition, errors: list):
    """A Split's tiles and the sums of its sizes."""
    policies = rule.values[0::3]
    for policy, size, arg in zip(policies, rule.values[1::3], definition.args[1::3]):
        if policy == TILE and isinstance(size, RandomSize):
            errors.append(Diagnostic(arg.location, "a Tile's size is fixed", "use rand for Abs or Rel parts"))
    if policies.count(TILE) > 1:
        second = [i for i, p in enumerate(policies) if p == TILE][1]
        errors.append(
            Diagnostic(
                definition.args[3 * second].location,
                "a Split has at most one Tile part",
                "nest a second Split for a second run of tiles",
            )
        )
    for policy, what in ((1, "relative"), (-1, "absolute")):
        total = sum(getattr(size, "high", size) for p, size in zip(policies, rule.values[1::3]) if p == policy)
        if total > limits.HALF_MAX:
            errors.append(
                Diagnostic(
                    definition.operator_location,
                    f"the {what} sizes add up to {total:g}, more than the GPU's 16-bit "
                    f"numbers hold ({limits.HALF_MAX:g})",
                    "use smaller sizes",
                )
            )


def _case_checks(rule: Rule, definition, errors: list):
    """A Case's conditions fit the GPU's token and stack limits."""
    conditions = rule.values[0:-1:2]
    tokens = sum(len(program(c)) + 1 for c in conditions)
    if tokens > limits.MAX_CASE_TOKENS:
        errors.append(
            Diagnostic(
                definition.operator_location,
                f"the conditions of this Case take {tokens} steps; the GPU limit is {limits.MAX_CASE_TOKENS}",
                "split it into two Cases",
            )
        )
    for condition, arg in zip(conditions, definition.args[0::2]):
        if stack_depth(condition) > limits.MAX_EXPR_STACK:
            errors.append(
                Diagnostic(
                    arg.location,
                    f"this condition nests deeper than {limits.MAX_EXPR_STACK} values",
                    "write it with fewer parentheses",
                )
            )


def _mat_checks(rule: Rule, definition, errors: list):
    """A fitted texture's or constant colour's rectangle lies in [0, 1]."""
    for start in range(1, len(rule.values), 5):
        tex, params = rule.values[start], rule.values[start + 1 : start + 5]
        outside = [i for i, p in enumerate(params) if not 0 <= p <= 1]
        if tex.fit and outside:
            arg = definition.args[start + 1 + outside[0]]
            what = "a constant colour" if tex.tile < 0 else "a fitted texture's rectangle"
            errors.append(Diagnostic(arg.location, f"{what} needs four values in [0, 1]"))


def _overhang_errors(rules: dict[str, Rule]) -> list[Diagnostic]:
    """An Overhang is drawn by the Split that holds it (the Split reads its margins): it may be
    referenced only as a Split's Abs or Rel part, by name (an alias of it is the same texels)."""

    def overhang(name: str) -> bool:
        rule = rules[name]
        while rule.operator == ALIAS and isinstance(rule.values[0], str):
            rule = rules[rule.values[0]]
        return rule.operator == "Overhang"

    found = []
    for rule in rules.values():
        definition = rule.source.definition
        for position, (value, kind) in enumerate(zip(rule.values, _kinds(rule.operator, len(rule.values)))):
            if kind is not Kind.RULE or not overhang(getattr(value, "name", value)):
                continue
            split_part = rule.operator in ("SplitX", "SplitY") and rule.values[position - 2] != TILE
            if isinstance(value, str) and (split_part or rule.operator == ALIAS):
                continue
            alias = rule.operator == ALIAS
            found.append(
                Diagnostic(
                    definition.operator_location if alias else definition.args[position].location,
                    f"{'a reference with arguments' if alias else rule.operator} cannot hold an Overhang",
                    "an Overhang is an Abs or Rel part of a SplitX or SplitY, named without arguments",
                )
            )
    return found


def _split_totals(rules: dict[str, Rule]) -> dict[str, set]:
    """The values split.total may have when each rule is reached (None: not known before run time,
    after a Repeat or a Tile); the facade's start scope has total 1."""
    referenced = {c for r in rules.values() for c in r.children}
    totals: dict[str, set] = {name: {1} for name in rules if name not in referenced}
    pending = list(totals)
    while pending:
        name = pending.pop()
        rule = rules[name]
        if rule.operator in ("SplitX", "SplitY"):
            handed = {None} if TILE in rule.values[0::3] else {len(rule.children)}
        elif rule.operator in ("RepeatX", "RepeatY"):
            handed = {None}
        else:
            handed = totals[name]
        for child in rule.children:
            known = totals.setdefault(child, set())
            if not handed <= known:
                known |= handed
                pending.append(child)
    return totals


def _index_errors(rules: dict[str, Rule]) -> list[Diagnostic]:
    """`split.index == k` in a Case where every Split that leads there has fewer than k + 1 parts."""
    found = []
    totals = _split_totals(rules)
    for name, rule in rules.items():
        possible = totals.get(name, set())
        if rule.operator != "Case" or not possible or None in possible:
            continue
        largest = max(possible)
        for condition in rule.values[0:-1:2]:
            for k, where in _index_equalities(condition):
                if not (k == int(k) and 0 <= k < largest):
                    found.append(
                        Diagnostic(
                            where,
                            f"split.index is never {k:g} here: it runs from 0 to {largest - 1} "
                            f"(the Splits that lead here have at most {largest} parts)",
                            "count parts from 0, or test split.last",
                        )
                    )
    return found


def _index_equalities(expr: Expr):
    """(k, location) of every `split.index == k` (either way round) in a condition."""
    if expr.op == "==":
        a, b = expr.args
        for var, num in ((a, b), (b, a)):
            if var.op == "var" and var.name == "split.index" and num.op == "num":
                yield num.value, expr.location
    for arg in expr.args:
        yield from _index_equalities(arg)


def _walk(rules: dict[str, Rule]) -> tuple[list[str], list[Diagnostic]]:
    """Every rule after all its children (a depth-first post-order), and every cycle of rule
    references, named (a cycle would never reach a terminal). Iterative: chains of any length."""
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done
    order: list[str] = []
    found: list[Diagnostic] = []
    for root in rules:
        if root in state:
            continue
        state[root], path, pending = 1, [root], [iter(rules[root].children)]
        while pending:
            child = next(pending[-1], None)
            if child is None:
                pending.pop()
                done = path.pop()
                state[done] = 2
                order.append(done)
            elif state.get(child) == 1:
                cycle = path[path.index(child) :] + [child]
                first = rules[child].source.definition
                found.append(
                    Diagnostic(
                        first.location,
                        "rules form a cycle: " + " -> ".join(cycle),
                        "every chain of rules must end in Mat, MatAlpha, Skip or SkipMask",
                    )
                )
            elif child not in state:
                state[child] = 1
                path.append(child)
                pending.append(iter(rules[child].children))
    return order, found


@dataclass(frozen=True)
class Cost:
    """Worst cases of one rule's evaluation, for the GPU's bounded loops."""

    steps: int
    layers: int
    stack: int
    intrusions: int

    def exceeded(self) -> list[str]:
        out = []
        if self.steps > limits.MAX_STEPS:
            out.append(f"up to {self.steps} operators per pixel (limit {limits.MAX_STEPS})")
        if self.layers > limits.MAX_LAYER_DEPTH:
            out.append(f"{self.layers} nested Layers (limit {limits.MAX_LAYER_DEPTH})")
        if self.stack > limits.MAX_STACK - 1:
            out.append(f"{self.stack} nested RandStacks (limit {limits.MAX_STACK - 1})")
        if self.intrusions > limits.MAX_INTRUSIONS:
            out.append(f"{self.intrusions} nested Intrusions (limit {limits.MAX_INTRUSIONS})")
        return out


def costs(rules: dict[str, Rule]) -> dict[str, Cost]:
    """Cost of every rule (the grammar must be acyclic)."""
    memo: dict[str, Cost] = {}
    for name in _walk(rules)[0]:  # children first
        rule = rules[name]
        kids = [memo[c] for c in rule.children]
        if not kids:
            memo[name] = Cost(1, 0, 0, 0)
            continue
        if rule.operator == ALIAS:
            memo[name] = replace(kids[0], steps=kids[0].steps + rule.binds)  # a Bind is one step
            continue
        steps = sum(k.steps for k in kids) if rule.operator == "Layer" else max(k.steps for k in kids)
        memo[name] = Cost(
            1 + steps + rule.binds * (len(kids) if rule.operator == "Layer" else 1),
            max(k.layers for k in kids) + (rule.operator == "Layer"),
            max(k.stack for k in kids) + (rule.operator == "RandStack"),
            max(k.intrusions for k in kids) + (rule.operator == "Intrusion"),
        )
    return memo


def _limit_errors(rules: dict[str, Rule]) -> list[Diagnostic]:
    table = costs(rules)
    found = []
    for name, rule in rules.items():
        over = table[name].exceeded()
        # Report where a limit is first crossed, not at every rule above it.
        if over and not any(table[c].exceeded() for c in rule.children):
            found.append(
                Diagnostic(
                    rule.source.definition.location,
                    f"rule '{name}' nests deeper than the GPU evaluator allows: " + "; ".join(over),
                    "flatten the grammar (fewer nested operators on one path)",
                )
            )
    return found
