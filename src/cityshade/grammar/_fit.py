"""The narrowest face a grammar fits: below it, its fixed-size parts (a door column, a window's
Abs width inside a Repeat's element) would overflow their scope, so a face narrower than that is
drawn as a plain wall instead (render/_facades.py). A face's level is known where it is drawn, so a
Case that chooses by facade.level alone (a ground floor with a door on level 0, storeys above)
counts with the choice it makes at that level; any other Case with its narrowest choice."""

from __future__ import annotations

import numpy as np

from ._checks import Grammar, RandomSize, Rule
from ._expressions import Expr, apply
from ._operators import POLICIES

ABS = POLICIES["Abs"]


def _size(value) -> float:
    return value.low if isinstance(value, RandomSize) else float(value)


def _level_condition(expr: Expr, level: int) -> float | None:
    """The value of a condition that reads only facade.level and numbers; None for any other."""
    if expr.op == "num":
        return expr.value
    if expr.op == "var":
        return float(level) if expr.name == "facade.level" else None
    args = [_level_condition(a, level) for a in expr.args]
    if any(a is None for a in args):
        return None
    return float(apply(expr.op, *(np.float32(a) for a in args)))


def _case_width(rule: Rule, widths: dict[str, float], level: int) -> float:
    """The narrowest of the choices a Case may make on a face at `level`."""
    choices = []
    for condition, child in zip(rule.values[:-1:2], rule.values[1:-1:2]):
        value = _level_condition(condition, level)
        if value == 0:
            continue  # never taken at this level
        choices.append(widths[getattr(child, "name", child)])
        if value is not None:
            return min(choices)  # always taken at this level: the choices after it never are
    else_rule = rule.values[-1]
    return min(choices + [widths[getattr(else_rule, "name", else_rule)]])


def _width(rule: Rule, widths: dict[str, float], level: int) -> float:
    if rule.operator == "Case":  # a Case may choose by the facade's width: the narrowest choice
        return _case_width(rule, widths, level)
    kids = [widths[name] for name in rule.children]
    if rule.operator == "SplitX":  # fixed parts keep their size; floating ones may shrink to what they hold
        parts = [rule.values[i : i + 3] for i in range(0, len(rule.values) - 2, 3)]
        return sum(
            max(_size(size), widths[getattr(child, "name", child)])
            if policy == ABS
            else widths[getattr(child, "name", child)]
            for policy, size, child in parts
        )
    return max(kids, default=0.0)  # every other operator: the widest of what it may run


def min_width(grammar: Grammar, level: int = 0) -> float:
    """Metres: the narrowest face at facade.level `level` on which every fixed-size part of the grammar fits."""
    widths: dict[str, float] = {}
    pending = [grammar.start]
    while pending:  # depth first, children before their rule (grammars are acyclic)
        name = pending[-1]
        rule = grammar.rules[name]
        todo = [c for c in rule.children if c not in widths]
        if todo:
            pending.extend(todo)
            continue
        pending.pop()
        widths[name] = _width(rule, widths, level)
    return widths[grammar.start]
