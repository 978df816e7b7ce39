"""Parsing, namespaces and the checks' error messages (each bad input named with file:line:col)."""

from __future__ import annotations

import pytest

from cityshade.grammar import GrammarError, compile_grammars, library_path, load, loads

WALL = "W->Mat(Color, Rep:wall1, 0, 0, 1, 1)\n"


def error_of(text: str, name: str = "bad.grammar") -> str:
    with pytest.raises(GrammarError) as info:
        loads(text, name)
    return str(info.value)


def test_fig12_parses_unchanged():
    grammar = load(library_path("fig12.grammar"))
    assert grammar.start == "S"
    assert len(grammar.rules) == 22
    assert grammar.rules["Skip"].operator == "Skip"  # a rule may share its operator's name
    assert grammar.rules["Assets"].children == ("BottomFloor", "Middle", "TopFloor")
    assert grammar.rules["Wall1"].values[1].code == -1  # Rep: tiles (m1 < 0), tile index 0 + 1


def test_semicolons_comments_and_multiline_arguments():
    grammar = loads("# a comment\nS->SplitX(Abs, 1.0, W,   # trailing comment\n   Rel, 2, W);\n" + WALL)
    assert grammar.rules["S"].values == (-1.0, 1.0, "W", 1.0, 2.0, "W")


def test_namespaces_reuse_and_override(tmp_path):
    (tmp_path / "base.grammar").write_text("Facade->RepeatX(2, Win)\nWin->Mat(Color, Fit>window1, 0, 0, 1, 1)\n")
    main = tmp_path / "main.grammar"
    main.write_text(
        'use "base.grammar" as Old\nuse "base.grammar" as New\n'
        "S->SplitY(Rel, 1, Old.Facade, Rel, 1, New.Facade)\n"
        "New.Win->Mat(Color, Fit>window3, 0, 0, 1, 1)\n"
    )
    grammar = load(main)
    assert grammar.start == "S"
    assert grammar.rules["Old.Facade"].children == ("Old.Win",)
    assert grammar.rules["New.Win"].values[1].tile != grammar.rules["Old.Win"].values[1].tile
    # the unchanged rules of both copies compile to the same texels only where they are identical
    compiled = compile_grammars({"main": grammar})
    assert compiled.address("main", "Old.Facade") != compiled.address("main", "New.Facade")


def test_identical_rules_share_texels():
    compiled = compile_grammars({"a": loads(WALL), "b": loads(WALL)})
    assert compiled.address("a") == compiled.address("b") and compiled.used == 1


def test_library_uses_namespaces_and_compiles_small():
    compiled = compile_grammars({"fig12": load(library_path("fig12.grammar"))})
    assert compiled.nbytes / 22 <= 16


@pytest.mark.parametrize(
    "text, expected",
    [
        (
            "S->SplitX(Rel, 1, Wal)\nWall->Skip(0)\n",
            ["bad.grammar:1:19: error: undefined rule 'Wal'", "did you mean the rule 'Wall'?"],
        ),
        (
            "S->SplitZ(Rel, 1, W)\n" + WALL,
            ["bad.grammar:1:4: error: unknown operator 'SplitZ'", "did you mean the operator 'Split"],
        ),
        (WALL + "W->Skip(0)\n", ["bad.grammar:2:1: error: rule 'W' is defined twice", "line 1"]),
        ("S->RepeatX(2)\n", ["bad.grammar:1:4: error: RepeatX takes (size, rule, [rounding]) but got 1 argument"]),
        ("S->SplitX(Rel, 1)\n", ["SplitX takes ((policy, size, rule)...) but got 2 arguments"]),
        ("S->RepeatX(W, 2)\n" + WALL, ["1:12: error: RepeatX expects a size in metres > 0 here, not 'W'"]),
        ("S->SplitX(Rell, 1, W)\n" + WALL, ["1:11: error: SplitX expects Abs, Rel or Tile here", "'Rel'"]),
        ("S->Mat(Colour, Rep:wall1, 0, 0, 1, 1)\n", ["1:8: error: Mat expects Color, Normal or Specular", "'Color'"]),
        ("S->Rand(0, 0.5, W, 0.4, W)\n" + WALL, ["1:4: error: Rand weights sum to 0.9, not 1"]),
        ("S->RepeatX(-2, W)\n" + WALL, ["1:12: error: size must be > 0, got -2"]),
        ("S->SplitY(Abs, 0, W)\n" + WALL, ["1:16: error: size must be > 0, got 0"]),
        ("S->Mat(Color, Rep:wal1, 0, 0, 1, 1)\n", ["1:15: error: unknown texture 'wal1'", "'wall1'"]),
        ("S->Mat(Color, Fit>window1, 0, 0, 2, 1)\n", ["1:34: error: a fitted texture's rectangle needs four values"]),
        ("S->Skip(1.5)\n", ["1:9: error: Skip expects a whole number >= 0 here, got 1.5"]),
        ("A->RepeatX(1, B)\nB->RepeatY(1, C)\nC->Layer(A, W)\n" + WALL, ["rules form a cycle: A -> B -> C -> A"]),
        ("S->Layer(W S)", ["1:12: error: unexpected 'S'; expected '(' or ')' or ','", "^", "is a ',' missing"]),
        ("S->Layer(W", ["the file ends in the middle of a rule"]),
        ("S Layer(W)", ["1:3: error: unexpected 'Layer'; expected '(' or '->'"]),
        ("", ["bad.grammar:1:1: error: the grammar is empty"]),
        ("# only a comment\n", ["the grammar is empty"]),
    ],
)
def test_bad_input_messages(text, expected):
    message = error_of(text)
    for part in expected:
        assert part in message, message


def test_caret_points_at_the_offending_text():
    lines = error_of("S->SplitX(Rel, 1, Wal)\n" + WALL).splitlines()
    assert lines[1].strip() == "S->SplitX(Rel, 1, Wal)"
    assert lines[2].index("^") == lines[1].index("Wal") and lines[2].endswith("^~~")


def test_all_errors_are_reported_together():
    message = error_of("S->SplitX(Rel, 1, A, Rel, 1, B)\n")
    assert "undefined rule 'A'" in message and "undefined rule 'B'" in message


def test_nesting_deeper_than_gpu_limit():
    text = "".join(f"L{i}->Layer(W, L{i + 1})\n" for i in range(6)) + "L6->Skip(0)\n" + WALL
    assert "nests deeper than the GPU evaluator allows: 5 nested Layers (limit 4)" in error_of(text)
    stacks = "".join(f"R{i}->RandStack(R{i + 1})\n" for i in range(9)) + "R9->Skip(0)\n"
    assert "nested RandStacks" in error_of(stacks)


@pytest.mark.parametrize(
    "argument, column",
    [("Layer(" * 3000 + "W" + ")" * 3000, 388), ("-" * 100_000 + "1", 78)],
)
def test_arguments_nested_thousands_deep_are_refused_at_the_limit(argument, column):
    message = error_of(f"S->Mat(Color, {argument}, 0, 0, 1, 1)\n" if argument[0] != "L" else f"S->{argument}\n")
    assert message.startswith(f"bad.grammar:1:{column}: error: arguments nest more than 64 levels deep"), message[:200]


def test_arguments_nested_within_the_limit_parse():
    from cityshade.grammar.testing import parse_text

    (rule,) = parse_text(f"S->Mat(Color, {'-' * 40}0.5, 0, 0, 1, 1)\n", "ok.grammar").rules
    assert rule.args[1].expr.op == "neg"


def test_more_rules_than_fit_the_texture():
    text = "S->RandUni(0, " + ", ".join(f"M{i}" for i in range(2100)) + ")\n"
    text += "".join(f"M{i}->Mat(Color, 0, {i / 2100:.6f}, 0.5, 0.5, 1)\n" for i in range(2100))
    with pytest.raises(GrammarError, match="texels; the grammar texture holds 2048"):
        compile_grammars({"big": loads(text)})


def test_binary_and_non_utf8_files(tmp_path):
    binary = tmp_path / "x.grammar"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0")
    with pytest.raises(GrammarError, match="x.grammar:1:1: error: this is a binary file"):
        load(binary)
    latin = tmp_path / "y.grammar"
    latin.write_bytes(b"S->Skip(0)\n# caf\xe9\n")
    with pytest.raises(GrammarError, match="y.grammar:2:6: error: the file is not UTF-8"):
        load(latin)


def test_missing_include_and_include_cycle(tmp_path):
    (tmp_path / "a.grammar").write_text('use "b.grammar" as B\nS->Skip(0)\n')
    (tmp_path / "b.grammar").write_text('use "a.grammar" as A\nT->Skip(0)\n')
    with pytest.raises(GrammarError, match="files include each other: a.grammar -> b.grammar -> a.grammar"):
        load(tmp_path / "a.grammar")
    (tmp_path / "c.grammar").write_text('use "nope.grammar" as N\nS->Skip(0)\n')
    with pytest.raises(GrammarError, match="included file 'nope.grammar' not found"):
        load(tmp_path / "c.grammar")


def test_a_bare_alias_is_its_target():
    grammar = loads("S -> Front\nFront->SplitX(Rel, 1, A, Rel, 1, W);\nA -> W;\n" + WALL)
    assert grammar.rules["S"].children == ("Front",) and grammar.rules["A"].children == ("W",)
    compiled = compile_grammars({"g": grammar})
    assert compiled.address("g") == compiled.address("g", "Front")
    assert compiled.address("g", "A") == compiled.address("g", "W")
    assert compiled.used == 2 + 1  # Front: a head and a texel of parts; W: one texel; aliases: none


def test_alias_errors_are_located():
    assert "bad.grammar:1:1: error: rules form a cycle: S -> T -> S" in error_of("S -> T\nT -> S\n")
    assert "bad.grammar:2:6: error: undefined rule 'X'" in error_of(WALL + "S -> X\n")


def test_an_alias_overrides_a_namespaced_rule(tmp_path):
    (tmp_path / "base.grammar").write_text("Facade->RepeatX(2, Win)\nWin->Mat(Color, Fit>window1, 0, 0, 1, 1)\n")
    main = tmp_path / "main.grammar"
    main.write_text(
        'use "base.grammar" as B\nS->Layer(B.Facade)\nB.Win->Arch\nArch->Mat(Color, Fit>window3, 0, 0, 1, 1)\n'
    )
    compiled = compile_grammars({"g": load(main)})
    assert compiled.address("g", "B.Win") == compiled.address("g", "Arch")
