"""Conditions of `Case`: arithmetic and comparisons on the split index and count, the scope's size,
the facade's size and level (the storey its bottom sits at) and the building's attributes (storeys,
style number, use, height), checked, folded and compiled to a short postfix program for the GPU.

    Floor->Case(split.first, Ground, split.index % 2 == 0 && scope.sx > 2, Even, Odd)
    Ground->Case(building.use == use.shop, Shops, Plain)

A program is a list of (code, value) tokens: push a number, push a variable, apply an operator.
`eval.glsl` runs it on a stack of GRAMMAR_MAX_EXPR_STACK values; the numpy twin runs the same
tokens. Division and modulo by zero give 0 at run time (a constant zero is an error at check time).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..scene import USES
from ._diagnostics import Diagnostic, Location, suggest

# Variable -> slot in the evaluator's variable vector (eval.glsl grammar_variable()).
VARIABLES = {
    "split.index": 0,
    "split.total": 1,
    "scope.sx": 2,
    "scope.sy": 3,
    "facade.width": 4,
    "facade.height": 5,
    "building.levels": 6,
    "building.style": 7,
    "building.use": 8,
    "building.height": 9,
    "facade.level": 10,
}
BUILDING = VARIABLES["building.levels"]  # the building's four attributes follow, in this order
FACADE_LEVEL = VARIABLES["facade.level"]
PARAMETER = len(VARIABLES)  # rule parameter k is variable PARAMETER + k
# Named numbers: building.use == use.office. The codes are the scene's (cityshade.scene.USES).
CONSTANTS = {f"use.{name}": float(code) for name, code in USES.items()}
# Shorthands written as other expressions.
DERIVED = {"split.first": "split.index == 0", "split.last": "split.index == split.total - 1"}

# Token codes (the first channel of a token; keep in step with eval.glsl grammar_condition()).
PUSH, VARIABLE, CASE = 0, 1, 2
BINARY = {
    "+": 3,
    "-": 4,
    "*": 5,
    "/": 6,
    "%": 7,
    "==": 8,
    "!=": 9,
    "<": 10,
    "<=": 11,
    ">": 12,
    ">=": 13,
    "&&": 14,
    "||": 15,
}
NOT, NEG = 16, 17


@dataclass(frozen=True)
class Expr:
    """A parsed expression: op is 'num', 'var', 'not', 'neg' or a binary operator."""

    op: str
    location: Location
    value: float = 0.0
    name: str = ""
    args: tuple["Expr", ...] = ()


def check_expr(expr: Expr, errors: list[Diagnostic], params: tuple[str, ...] = ()) -> Expr | None:
    """Resolves variables (and the rule's parameters) and folds constants; a bad name or a
    constant zero divisor is an error."""
    if expr.op == "num":
        return expr
    if expr.op == "var":
        if expr.name in DERIVED:
            from ._syntax import parse_expression

            return check_expr(parse_expression(DERIVED[expr.name], expr.location), errors)
        if expr.name in params:
            return Expr("var", expr.location, name=expr.name, value=PARAMETER + params.index(expr.name))
        if expr.name in CONSTANTS:
            return Expr("num", expr.location, value=CONSTANTS[expr.name])
        if expr.name.startswith("use."):
            errors.append(
                Diagnostic(
                    expr.location,
                    f"unknown use '{expr.name}'",
                    suggest(expr.name, list(CONSTANTS), "use") or "uses: " + ", ".join(CONSTANTS),
                )
            )
            return None
        if expr.name not in VARIABLES:
            names = list(VARIABLES) + list(DERIVED) + list(params)
            errors.append(
                Diagnostic(
                    expr.location,
                    f"unknown variable '{expr.name}' in a condition",
                    suggest(expr.name, names, "variable") or "variables: " + ", ".join(names),
                )
            )
            return None
        return expr
    if expr.op == "call":
        errors.append(
            Diagnostic(
                expr.location,
                f"'{expr.name}(...)' cannot be used in a condition",
                "conditions use numbers, variables and operators",
            )
        )
        return None
    args = [check_expr(a, errors, params) for a in expr.args]
    if any(a is None for a in args):
        return None
    if expr.op in ("/", "%") and args[1].op == "num" and args[1].value == 0:
        errors.append(Diagnostic(expr.location, f"'{expr.op}' by zero", "divide by a number that is not 0"))
        return None
    folded = Expr(expr.op, expr.location, args=tuple(args))
    if all(a.op == "num" for a in args):
        return Expr("num", expr.location, value=evaluate_constant(folded))
    return folded


def apply(op: str, a, b=None, xp=None):
    """One operator on numbers or float32 arrays (xp: numpy for arrays), as eval.glsl applies it."""
    import numpy as np

    xp = xp or np
    f = np.float32
    if op == "not":
        return xp.where(a == 0, f(1), f(0))
    if op == "neg":
        return -a
    if op in ("/", "%"):
        safe = xp.where(b == 0, f(1), b)
        out = a / safe if op == "/" else a - safe * xp.floor(a / safe)
        return xp.where(b == 0, f(0), out).astype(f)
    table = {
        "+": lambda: a + b,
        "-": lambda: a - b,
        "*": lambda: a * b,
        "==": lambda: a == b,
        "!=": lambda: a != b,
        "<": lambda: a < b,
        "<=": lambda: a <= b,
        ">": lambda: a > b,
        ">=": lambda: a >= b,
        "&&": lambda: (a != 0) & (b != 0),
        "||": lambda: (a != 0) | (b != 0),
    }
    return xp.asarray(table[op]()).astype(f)


def evaluate_constant(expr: Expr) -> float:
    import numpy as np

    return float(apply(expr.op, *(np.float32(a.value) for a in expr.args)))


def program(expr: Expr) -> list[tuple[float, float]]:
    """Postfix tokens (code, value) of a checked expression."""
    if expr.op == "num":
        return [(PUSH, expr.value)]
    if expr.op == "var":
        return [(VARIABLE, VARIABLES.get(expr.name, expr.value))]
    tokens = [t for a in expr.args for t in program(a)]
    code = {"not": NOT, "neg": NEG}.get(expr.op) or BINARY[expr.op]
    return tokens + [(code, 0.0)]


def stack_depth(expr: Expr) -> int:
    """Stack slots the postfix program needs."""
    if not expr.args:
        return 1
    return max(stack_depth(a) + i for i, a in enumerate(expr.args))
