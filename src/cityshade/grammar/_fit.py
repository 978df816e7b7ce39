"""The narrowest face a grammar fits: below it, its fixed-size parts (a door column, a window's
Abs width inside a Repeat's element) would overflow their scope, so a face narrower than that is
drawn as a plain wall instead (render/_facades.py)."""

from __future__ import annotations

from ._checks import Grammar, RandomSize, Rule
from ._operators import POLICIES

ABS = POLICIES["Abs"]


def _size(value) -> float:
    return value.low if isinstance(value, RandomSize) else float(value)


def _width(rule: Rule, widths: dict[str, float]) -> float:
    kids = [widths[name] for name in rule.children]
    if rule.operator == "SplitX":  # fixed parts keep their size; floating ones may shrink to what they hold
        parts = [rule.values[i : i + 3] for i in range(0, len(rule.values) - 2, 3)]
        return sum(
            max(_size(size), widths[getattr(child, "name", child)])
            if policy == ABS
            else widths[getattr(child, "name", child)]
            for policy, size, child in parts
        )
    if rule.operator == "Case":  # a Case may choose by the facade's width: the narrowest choice
        return min(kids)
    return max(kids, default=0.0)  # every other operator: the widest of what it may run


def min_width(grammar: Grammar) -> float:
    """Metres: the narrowest face on which every fixed-size part of the grammar fits."""
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
        widths[name] = _width(rule, widths)
    return widths[grammar.start]
