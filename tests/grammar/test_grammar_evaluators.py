"""What `grammar check` accepts, both evaluators evaluate: rules in the texture's last texels,
nests as deep as the GPU's step limit; longer chains are refused with FILE:LINE:COL."""

from __future__ import annotations

import pytest

from cityshade.grammar import GrammarError, compile_grammars, loads
from grammar_compare import compare, ctx  # noqa: F401  (ctx is a fixture)

LEAVES = "A->Mat(Color, Rep:wall1, 0.0, 0.0, 1.0, 1.0)\nB->Mat(Color, Rep:wall3, 0.0, 0.0, 1.0, 1.0)\n"


def _at_the_end(last_rule: str, texels: int = 256) -> str:
    """A grammar whose rule Z is compiled into the last texels of a full texture row: two-texel
    filler rules, and a one-texel one if needed, are placed before it."""
    for count in range(texels // 2):
        for extra in ("", "P->Mat(Color, Rep:wall4, 0.0, 0.0, 1.0, 1.0)\n"):
            fillers = "".join(f"F{i}->Mat(Color, Rep:wall2, 0.0, 0.0, 1.0, {1 + i / 64:.6f})\n" for i in range(count))
            text = "S->Skip(0)\n" + LEAVES + fillers + extra + last_rule
            if compile_grammars({"g": loads(text)}).used == texels:
                return text
    raise AssertionError("no filler count fills the row")


@pytest.mark.parametrize(
    "rule, terminals",
    [
        ("Z->SplitX(Rel, 1.0, A, Rel, 1.0, B)\n", 2),
        ("Z->Rand(0, 0.5, A, 0.5, B)\n", 1),  # one choice per facade
        ("Z->SplitY(Abs, 2.0, A, Rel, 1.0, B, Abs, 3.0, A)\n", 2),
    ],
)
def test_rules_in_the_last_texels_evaluate_alike(ctx, rule, terminals, output_dir):  # noqa: F811
    compiled = compile_grammars({"g": loads(_at_the_end(rule))})
    assert compiled.used == 256 and compiled.address("g", "Z") + 4 > 256, "Z is not in the last texels"
    compiled.starts["g"] = "Z"
    compare(ctx, compiled, "g", output_dir, size=(64, 48), min_terminals=terminals)


def _nest(depth: int) -> str:
    rules = [f"R{i}->SplitX(Abs, 0.1, B, Rel, 1.0, R{i + 1})" for i in range(depth)]  # 0.1 m per level
    return "\n".join(rules) + f"\nR{depth}->Mat(Color, Rep:wall1, 0.0, 0.0, 1.0, 1.0)\n" + LEAVES


def test_a_nest_as_deep_as_the_step_limit_evaluates_alike(ctx, output_dir):  # noqa: F811
    compiled = compile_grammars({"g": loads(_nest(126))})
    compare(ctx, compiled, "g", output_dir, size=(64, 48))


@pytest.mark.parametrize("depth", [128, 500, 5000])
def test_longer_chains_are_refused_with_a_location(depth):
    with pytest.raises(GrammarError) as info:
        loads(_nest(depth))
    first = str(info.value).splitlines()[0]
    assert first.startswith("<string>:") and "nests deeper than the GPU evaluator allows" in first
