"""Lays checked grammars out in one RGBA 16-bit float texture, as in §4 and fig. 3.

Each rule occupies consecutive texels from its address; the first channel is the operator code.
Rule references are texel addresses (one channel each; exact integers in half floats below
2048). Split stores the precomputed sums of its relative and absolute sizes, Rand the
accumulated weights, and every variable-length operator its part count n, which bounds its
loop. Case stores its conditions as postfix (code, value) tokens. A Split with a Tile part keeps the tile's size in a second texel. Rules that compile to the same texels share one address, so styles that vary a few
rules of another (namespaces) cost only the rules they change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _limits as limits
from ._checks import Bound, Grammar, RandomSize, Rule, TexRef
from ._diagnostics import Diagnostic, GrammarError
from ._expressions import CASE, program
from ._operators import ALIAS, BIND_OPCODE, OPERATORS, TILE

_UNIT_RECT = (0.0, 0.0, 1.0, 1.0)


@dataclass(frozen=True)
class CompiledGrammars:
    """The grammar texture and where each rule of each grammar starts."""

    texels: np.ndarray  # (rows, TEXTURE_WIDTH, 4) float16
    used: int  # texels holding rules
    addresses: dict[tuple[str, str], int]  # (grammar name, rule name) -> address
    starts: dict[str, str]  # grammar name -> its start rule

    @property
    def nbytes(self) -> int:
        """Bytes the rules occupy (the paper's §6 measure: used texels x 8 bytes)."""
        return self.used * self.texels.itemsize * 4

    def address(self, grammar: str, rule: str | None = None) -> int:
        return self.addresses[(grammar, rule or self.starts[grammar])]

    def flat(self) -> np.ndarray:
        """Texels as (rows * width, 4) float32, indexed by address."""
        return self.texels.reshape(-1, 4).astype(np.float32)


def _encode(rule: Rule, address_of) -> list[list[float]]:
    """A rule's texels: its operator's opcode and values, laid out by that operator's encoder."""
    return _ENCODERS[rule.operator](OPERATORS[rule.operator].opcode, rule.values, address_of)


def _encode_repeat(op, v, address_of):
    rounding = v[2] if len(v) > 2 else 0
    if isinstance(v[0], RandomSize):  # head.w + 2 flags rand(low, high): high in the next texel
        return [[op, v[0].low, address_of(v[1]), rounding + 2], [v[0].high, 0, 0, 0]]
    return [[op, v[0], address_of(v[1]), rounding]]


def _encode_split(op, v, address_of):
    # A part is (size, rule): size < 0 absolute, > 0 floating; a tile's rule is stored as
    # -(address + 1), and a split with a tile has -n in its head and the tile's size next.
    # With rand sizes, n + RANDOM_PARTS in the head, each part's low in its pair and the highs
    # in texels after the pairs; the sums are then made per scope by the evaluators.
    policies, sizes, children = v[0::3], v[1::3], v[2::3]
    low = [getattr(size, "low", size) for size in sizes]
    parts = [
        (size if policy == TILE else policy * size, -address_of(child) - 1 if policy == TILE else address_of(child))
        for policy, size, child in zip(policies, low, children)
    ]
    rel = sum(size for policy, size in zip(policies, low) if policy == 1)
    absolute = sum(size for policy, size in zip(policies, low) if policy < 0)
    tiles = [size for policy, size in zip(policies, low) if policy == TILE]
    random = any(isinstance(size, RandomSize) for size in sizes)
    count = len(parts) + (limits.RANDOM_PARTS if random else 0)
    head = [[op, -count if tiles else count, rel, absolute]] + ([[tiles[0], 0, 0, 0]] if tiles else [])
    highs = _packed([], [getattr(size, "high", size) for size in sizes]) if random else []
    return head + _pairs(parts) + highs


def _encode_color(op, v, address_of):  # a constant Mat whose head.w, above 1, is 1 + its label
    label = v[3] if len(v) > 3 else 0
    return [[op, 1, 0, 1 + label], [v[0], v[1], v[2], 1.0]]


def _encode_case(op, v, address_of):
    # Each condition's postfix tokens, then (CASE, its rule): the first true one is taken,
    # else the last rule (in the head).
    tokens = []
    for condition, child in zip(v[0:-1:2], v[1:-1:2]):
        tokens += program(condition) + [(CASE, address_of(child))]
    return [[op, len(tokens), address_of(v[-1]), 0]] + _pairs(tokens)


def _encode_rand(op, v, address_of):
    weights = np.cumsum(v[1::2])
    weights[-1] = 1.0
    parts = [(float(a), address_of(child)) for a, child in zip(weights, v[2::2])]
    return [[op, len(parts), v[0], 0]] + _pairs(parts)


def _encode_intrusion(op, v, address_of):
    refs = [address_of(c) for c in v[1:]]
    return [[op, v[0], refs[0], refs[1]], [refs[2], refs[3], refs[4], 0]]


def _encode_mat(op, v, address_of):
    usage, tex, params = v[0], v[1], tuple(v[2:6])
    if tex.tile >= 0 and params == _UNIT_RECT:
        return [[op, usage, tex.code, 0]]  # the common case: one texel
    return [[op, usage, tex.code, 1], list(params)]


def _encode_mat_alpha(op, v, address_of):
    alpha_tex: TexRef = v[6]
    return [[op, v[0], v[1].code, alpha_tex.code], list(v[2:6]), list(v[7:11])]


_ENCODERS = {
    "RepeatX": _encode_repeat,
    "RepeatY": _encode_repeat,
    "SplitX": _encode_split,
    "SplitY": _encode_split,
    "Color": _encode_color,
    "Tint": lambda op, v, address_of: [[op, address_of(v[3]), 0, 0], [v[0], v[1], v[2], 0]],
    # an Overhang's Split reads the margins and runs the rule in the enlarged part
    "Overhang": lambda op, v, address_of: [[op, v[0], v[1], address_of(v[2])]],
    "Case": _encode_case,
    "Rand": _encode_rand,
    "RandUni": lambda op, v, address_of: _packed([op, len(v) - 1, v[0]], [address_of(c) for c in v[1:]]),
    "RandStack": lambda op, v, address_of: [[op, address_of(v[0]), 0, 0]],
    "Layer": lambda op, v, address_of: _packed([op, len(v)], [address_of(c) for c in v]),
    "Skip": lambda op, v, address_of: [[op, v[0], 0, 0]],
    "SkipMask": lambda op, v, address_of: [[op, v[0].code, v[1], v[2]]],
    "Intrusion": _encode_intrusion,
    "Mat": _encode_mat,
    "MatAlpha": _encode_mat_alpha,
}


def _pairs(parts: list[tuple[float, int]]) -> list[list[float]]:
    flat = [x for part in parts for x in part]
    flat += [0.0] * (-len(flat) % 4)
    return [flat[i : i + 4] for i in range(0, len(flat), 4)]


def _packed(head: list[float], refs: list[int]) -> list[list[float]]:
    flat = head + refs
    flat += [0.0] * (-len(flat) % 4)
    return [flat[i : i + 4] for i in range(0, len(flat), 4)]


def compile_grammars(grammars: dict[str, Grammar]) -> CompiledGrammars:
    """All rules of all grammars into one texture; raises GrammarError when they do not fit."""
    texels: list[list[float]] = []
    by_content: dict[tuple, int] = {}
    addresses: dict[tuple[str, str], int] = {}

    def place(code: list[list[float]]) -> int:
        content = tuple(np.float16(x).item() for texel in code for x in texel)
        if content not in by_content:
            by_content[content] = len(texels)
            texels.extend(code)
        return by_content[content]

    for gname, grammar in grammars.items():

        def address_of(rule_name, grammar=grammar, gname=gname) -> int:
            if isinstance(rule_name, Bound):  # the Bind texels: the arguments' tokens, then the rule
                tokens = [t for value in rule_name.args for t in program(value)]
                head = [BIND_OPCODE, len(tokens), address_of(rule_name.name), len(rule_name.args)]
                return place([head] + _pairs(tokens))
            key = (gname, rule_name)
            if key not in addresses:
                rule = grammar.rules[rule_name]
                if rule.operator == ALIAS:
                    addresses[key] = address_of(rule.values[0])
                    return addresses[key]
                addresses[key] = place(_encode(rule, address_of))
            return addresses[key]

        for rule_name in grammar.rules:
            address_of(rule_name)
    if len(texels) > limits.MAX_TEXELS:
        first = next(iter(grammars.values()))
        where = first.rules[first.start].source.definition.location
        raise GrammarError(
            [
                Diagnostic(
                    where,
                    f"the rules need {len(texels)} texels; the grammar texture holds {limits.MAX_TEXELS}",
                    "split the styles over fewer rules",
                )
            ],
            first.sources,
        )
    rows = max(1, -(-len(texels) // limits.TEXTURE_WIDTH))
    data = np.zeros((rows * limits.TEXTURE_WIDTH, 4), np.float32)
    if texels:
        data[: len(texels)] = np.asarray(texels, np.float32)
    return CompiledGrammars(
        data.astype(np.float16).reshape(rows, limits.TEXTURE_WIDTH, 4),
        len(texels),
        addresses,
        {g: gr.start for g, gr in grammars.items()},
    )
