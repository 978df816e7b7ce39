"""The operators of fig. 3: their argument signatures, opcodes and the grammar's named constants."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class Kind(Enum):
    """What an argument position accepts."""

    RULE = "a rule name"
    SIZE = "a size in metres > 0"
    WEIGHT = "a weight in (0, 1]"
    COUNT = "a whole number >= 0"
    POLICY = "Abs, Rel or Tile"
    ROUNDING = "Nearest or Ceil"
    USAGE = "Color, Normal or Specular"
    TEXTURE = "0 or a texture Rep:name / Fit>name"
    MASK = "a mask Fit>name / Rep:name"
    NUMBER = "a number"
    CONDITION = "a condition"
    FRACTION = "a number in [0, 1]"
    LABEL = "a label"
    MARGIN = "a margin in metres in [0, 1]"


# Split's part sizes: absolute metres; relative, i.e. floating (CGA's `~`): these share what the
# absolute parts leave, scaled by one factor; or a tile repeated the nearest whole number of times,
# its copies floating with the same factor as the relative parts beside it (CGA's `{~v: R}*`).
POLICIES = {"Abs": -1.0, "Rel": 1.0, "Tile": 2.0}
TILE = POLICIES["Tile"]
USAGES = {"Color": 1, "Normal": 2, "Specular": 3}
# Repeat's tile count: the nearest whole number of tiles (CGA's rule, the default) or the
# paper's ceil(S / v) (eq. in §3.1), which never makes a tile wider than asked.
ROUNDINGS = {"Nearest": 0, "Ceil": 1}


@dataclass(frozen=True)
class Signature:
    """`head` arguments, then `group` repeated at least `min_groups` times (no group: fixed arity),
    or, for fixed arities, the `optional` arguments that may follow the head; `tail` follows the groups."""

    opcode: int
    head: tuple[Kind, ...]
    group: tuple[Kind, ...] = ()
    min_groups: int = 0
    optional: tuple[Kind, ...] = ()
    tail: tuple[Kind, ...] = ()

    def describe(self) -> str:
        parts = [k.name.lower() for k in self.head] + [f"[{k.name.lower()}]" for k in self.optional]
        if self.group:
            parts.append("(" + ", ".join(k.name.lower() for k in self.group) + ")...")
        parts += [k.name.lower() for k in self.tail]
        return ", ".join(parts)

    def arity_ok(self, count: int) -> bool:
        rest = count - len(self.head) - len(self.tail)
        if not self.group:
            return 0 <= rest <= len(self.optional)
        return rest >= len(self.group) * self.min_groups and rest % len(self.group) == 0


_MAT = (Kind.USAGE, Kind.TEXTURE, Kind.NUMBER, Kind.NUMBER, Kind.NUMBER, Kind.NUMBER)

ALIAS = "->"  # the operator of an alias `A->B`: A is B (it has no texels of its own)

# Opcodes are the paper's (fig. 3): the first channel of a rule's first texel.
OPERATORS: dict[str, Signature] = {
    "RepeatX": Signature(1, (Kind.SIZE, Kind.RULE), optional=(Kind.ROUNDING,)),
    "RepeatY": Signature(2, (Kind.SIZE, Kind.RULE), optional=(Kind.ROUNDING,)),
    "SplitX": Signature(3, (), (Kind.POLICY, Kind.SIZE, Kind.RULE), 1),
    "SplitY": Signature(4, (), (Kind.POLICY, Kind.SIZE, Kind.RULE), 1),
    "Rand": Signature(5, (Kind.COUNT,), (Kind.WEIGHT, Kind.RULE), 1),
    "RandUni": Signature(6, (Kind.COUNT,), (Kind.RULE,), 1),
    "RandStack": Signature(7, (Kind.RULE,)),
    "Layer": Signature(8, (), (Kind.RULE,), 1),
    "Skip": Signature(9, (Kind.COUNT,)),
    "SkipMask": Signature(10, (Kind.MASK, Kind.COUNT, Kind.COUNT)),
    "Intrusion": Signature(11, (Kind.SIZE,) + (Kind.RULE,) * 5),
    "Mat": Signature(12, _MAT),
    "MatAlpha": Signature(13, _MAT + _MAT[1:]),
    # A constant opaque colour with a semantic label: compiled as a constant Mat (opcode 12).
    "Color": Signature(12, (Kind.FRACTION, Kind.FRACTION, Kind.FRACTION), optional=(Kind.LABEL,)),
    # Multiplies the colour of every colour Mat below it by (r, g, b): a tinted texture.
    "Tint": Signature(16, (Kind.FRACTION, Kind.FRACTION, Kind.FRACTION, Kind.RULE)),
    # A Split part drawn `before` and `after` metres past its own ends, over its neighbours.
    "Overhang": Signature(17, (Kind.MARGIN, Kind.MARGIN, Kind.RULE)),
    "Case": Signature(14, (), (Kind.CONDITION, Kind.RULE), 1, tail=(Kind.RULE,)),
    ALIAS: Signature(0, (Kind.RULE,)),
}
# Floor(split.index) as a reference: computes the arguments into the parameters, then goes on to
# the rule. Made by the compiler, never written.
BIND_OPCODE = 15
