"""`cityshade grammar import FILE.cga`: CGA translated into a grammar that checks and renders
alike on the GPU and numpy, every dropped construct listed by line, bad input refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cityshade.assets import LABELS
from cityshade.commands import main
from cityshade.grammar import CgaError, GrammarError, compile_grammars, loads, translate
from grammar_compare import compare, ctx  # noqa: F401  (ctx is a fixture)

DATA = Path(__file__).parents[1] / "data" / "cga"


@pytest.mark.parametrize(
    "name, notes",
    [
        ("tutorial_facade", [18, 22, 51, 52, 53, 54, 57, 60, 61, 64]),
        ("conditions_facade", [18, 19, 32, 37, 42, 44]),
    ],
)
def test_cga_files_translate_check_and_render_alike(ctx, name, notes, output_dir):  # noqa: F811
    translation = translate((DATA / f"{name}.cga").read_text(), name)
    assert sorted({n.line for n in translation.notes}) == sorted(set(notes))
    compiled = compile_grammars({name: loads(translation.text, f"{name}.grammar")})
    compare(
        ctx, compiled, name, output_dir, facade=(30.0, 16.0), size=(150, 80), min_terminals=3, nearest=False, allowed=0
    )


def test_translation_keeps_the_structure():
    text = translate((DATA / "tutorial_facade.cga").read_text()).text
    assert "Lot->Building\nBuilding->Facade\n" in text  # extrude and comp dropped, the front kept
    assert "SplitX(Abs, 1, Wall, Tile, 4.2, Tile, Abs, 1, Wall)" in text  # {~tileW: Tile}* beside walls
    text = translate((DATA / "conditions_facade.cga").read_text()).text
    assert "Floor(i)->Case(i == 0, Floor_1, split.index % 2 == 1 && scope.sx > 10, Floor_2, 0, NIL, Floor_3)" in text
    assert "Rand(0, 0.3000, Shop_5, 0.5000, Shop_7, 0.2000, ShopFront)" in text
    assert "Upper->RepeatY(3.2, Floor(split.index))" in text  # a rule parameter passed on


def test_the_command_reports_and_writes(tmp_path, capsys):
    out = tmp_path / "t.grammar"
    assert main(["grammar", "import", str(DATA / "conditions_facade.cga"), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "conditions_facade.cga:19: condition 'inside' uses inside: the condition is taken as false" in err
    assert "6 constructs not translated as written" in err
    assert out.read_text().startswith("# Translated from conditions_facade.cga")
    assert main(["grammar", "check", str(out)]) == 0


@pytest.mark.parametrize(
    "content, message",
    [
        (b"\x00\x01\x02", "this is a binary file"),
        (b"attr x = 3\n", "no rules found; nothing was written"),
        (b"caf\xe9 --> X\n", "not UTF-8"),
    ],
)
def test_bad_cga_is_one_line_and_writes_nothing(tmp_path, capsys, content, message):
    source, out = tmp_path / "bad.cga", tmp_path / "bad.grammar"
    source.write_bytes(content)
    assert main(["grammar", "import", str(source), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and not out.exists()


def test_a_value_of_a_hundred_thousand_unary_minuses_is_not_evaluated():
    minuses = "-" * 100_000
    text = f'attr h = {minuses}3\nLot --> split(y) {{ h : A | {minuses}2 : B }}\nA --> color("#ff0000")\nB --> NIL\n'
    translation = translate(text, "minus.cga")
    assert [note.format("minus.cga") for note in translation.notes[:2]] == [
        "minus.cga:1: a value of 100001 tokens: not evaluated; it is unknown",
        "minus.cga:2: size 'h': not a positive number here; 1 is used",
    ]
    assert "Lot->SplitY(Abs, 1, A," in translation.text


@settings(max_examples=60, deadline=None)
@given(st.text(alphabet="AB xy{}()[]|:~'*%=.,-->0123456789\n\"#split case else color", max_size=120))
def test_any_text_translates_or_is_refused(text):
    try:
        translation = translate(text)
    except CgaError as exc:
        assert "error:" in str(exc)
        return
    assert translation.text.endswith("\n")
    try:  # what the command then checks: a GrammarError (exit 2, located) is the only failure
        loads(translation.text)
    except GrammarError:
        pass


def test_recursive_cga_is_refused_with_the_reason(tmp_path, capsys):
    source, out = tmp_path / "rec.cga", tmp_path / "rec.grammar"
    source.write_text('A --> split(x){ ~1 : A | 2 : B }\nB --> color("#ffffff")\n')
    assert main(["grammar", "import", str(source), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "the translation does not check (recursive rules" in err and "rules form a cycle: A -> A" in err
    assert not out.exists()


def test_a_colour_before_a_texture_tints_it():
    text = translate('Wall --> color("#ffcc99") texture("brick.jpg")\nPlain --> color("#888888") Wall\n').text
    assert "Wall->Tint(1.000, 0.800, 0.600, Wall_1)\nWall_1->Mat(Color, Rep:wall1, 0, 0, 0.5, 0.5)\n" in text
    assert "Plain->Layer(Plain_2, Wall)\nPlain_2->Color(0.533, 0.533, 0.533)\n" in text  # a colour under successors
    loads(text)


PUBLIC = DATA / "cgajs"  # real public CGA files (README.md there: source and licence)


@pytest.mark.parametrize(
    "name, labels",
    [
        ("house", {"wall", "window", "door"}),
        ("officebuilding", {"wall", "cornice", "window"}),
        ("castle", {"wall", "door", "none"}),  # none: the battlement gaps (NIL)
        ("church", {"wall", "none"}),
        ("tut5", {"wall"}),
    ],
)
def test_public_cga_files_translate_with_a_report_check_and_render_alike(ctx, name, labels, output_dir):  # noqa: F811
    source = (PUBLIC / f"{name}.cga").read_text()
    translation = translate(source, f"{name}.cga")  # never a traceback: CgaError is the only refusal
    lines = len(source.splitlines())
    assert translation.notes and all(1 <= n.line <= lines for n in translation.notes)  # what was dropped, by line
    compiled = compile_grammars({name: loads(translation.text, f"{name}.grammar")})
    cpu, _ = compare(
        ctx, compiled, name, output_dir, facade=(3.0, 2.0), size=(96, 64), min_terminals=1, nearest=False, allowed=0
    )
    assert {LABELS[v] for v in np.unique(cpu.label)} == labels


def test_public_cga_colours_and_labels_follow_the_rules():
    text = translate((PUBLIC / "house.cga").read_text()).text
    assert "Window->Color(0.678, 0.847, 0.902, window)" in text  # color("lightblue") in rule Window
    assert "Door->Color(0.502, 0.502, 0.502, door)" in text  # color("grey")
    assert "Side_5->SplitX(Tile, 0.9, Side_3)" in text  # {'0.3: W | ~0.3: WindowWall | '0.3: Wall}*
    notes = [n.what for n in translate((PUBLIC / "tut5.cga").read_text()).notes]
    assert "color(rand ( 32 , 255 ) , rand ( 32 , 255 ) , rand ( 32 , 255 ))" in notes  # random channels: listed
