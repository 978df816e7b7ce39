"""`use` reads only grammar files inside the grammar's folder or the library, and never quotes
the content of a file that is not a grammar."""

from __future__ import annotations

import pytest

from cityshade.commands import main
from cityshade.grammar import GrammarError, load, loads

SECRET = "root:$6$SECRETHASH:19000:0:99999:7:::"


@pytest.fixture
def secret(tmp_path):
    outside = tmp_path / "private"
    outside.mkdir()
    (outside / "shadow").write_text(SECRET + "\n")
    (outside / "shadow.grammar").write_text(SECRET + "\n")
    (outside / "ok.grammar").write_text("T->Skip(0)\n")
    folder = tmp_path / "styles"
    folder.mkdir()
    return tmp_path, folder


@pytest.mark.parametrize(
    "target",
    [
        "{root}/private/shadow",  # absolute, not a .grammar
        "../private/shadow",  # relative, leaves the folder
        "{root}/private/shadow.grammar",  # absolute grammar outside the folder
        "../private/ok.grammar",  # a valid grammar, but outside the folder
        "/proc/self/environ",
    ],
)
def test_use_outside_the_folder_or_not_a_grammar_is_refused_without_quoting(secret, target, capsys):
    root, folder = secret
    main_file = folder / "main.grammar"
    main_file.write_text(f'use "{target.format(root=root)}" as X\nS->Skip(0)\n')
    with pytest.raises(GrammarError) as info:
        load(main_file)
    message = str(info.value)
    assert "SECRET" not in message and "root:" not in message
    assert message.startswith(f"{main_file}:1:")
    assert main(["grammar", "check", str(main_file)]) == 1
    assert "SECRET" not in capsys.readouterr().err


def test_a_link_out_of_the_folder_is_refused(secret):
    root, folder = secret
    (folder / "link.grammar").symlink_to(root / "private" / "ok.grammar")
    (folder / "main.grammar").write_text('use "link.grammar" as X\nS->Skip(0)\n')
    with pytest.raises(GrammarError, match="not found"):
        load(folder / "main.grammar")


def test_an_included_file_that_does_not_parse_is_not_quoted(secret):
    root, folder = secret
    (folder / "bad.grammar").write_text("A->Skip(0)\n" + SECRET + "\n")
    (folder / "main.grammar").write_text('use "bad.grammar" as X\nS->Skip(0)\n')
    with pytest.raises(GrammarError) as info:
        load(folder / "main.grammar")
    message = str(info.value)
    assert "bad.grammar:2:" in message and "SECRETHASH" not in message and "19000" not in message


def test_a_file_named_on_the_command_line_is_quoted_only_if_it_is_a_grammar(tmp_path, capsys):
    secret = tmp_path / "notes.txt"
    secret.write_text("password = " + SECRET + "\n")
    assert main(["grammar", "check", str(secret)]) == 1
    err = capsys.readouterr().err
    assert f"{secret}:1:" in err and "SECRETHASH" not in err
    mine = tmp_path / "mine.grammar"
    mine.write_text("S->Skip(0)\nT->Skip(0 0)\n")
    assert main(["grammar", "check", str(mine)]) == 1
    assert "T->Skip(0 0)" in capsys.readouterr().err  # the author's own grammar: line and caret


def test_a_grammar_named_link_to_a_file_elsewhere_is_not_quoted(secret, capsys):
    root, folder = secret
    for name, target in (("shadow.grammar", "shadow"), ("outside.grammar", "shadow.grammar")):
        (folder / name).symlink_to(root / "private" / target)
        assert main(["grammar", "check", str(folder / name)]) == 1
        err = capsys.readouterr().err
        assert f"{folder / name}:1:" in err and "SECRETHASH" not in err
    (folder / "mine.grammar").write_text("S->Skip(0)\nT->Skip(0 0)\n")
    (folder / "same.grammar").symlink_to(folder / "mine.grammar")  # a link within the folder is the author's
    assert main(["grammar", "check", str(folder / "same.grammar")]) == 1
    assert "T->Skip(0 0)" in capsys.readouterr().err


def test_a_byte_order_mark_is_skipped_as_cga_import_skips_it(tmp_path):
    path = tmp_path / "bom.grammar"
    path.write_bytes(b"\xef\xbb\xbfS->Mat(Color, Rep:wall1, 0.0, 0.0, 1.0, 1.0)\n")
    assert load(path).start == "S"
    path.write_bytes(b"\xef\xbb\xbfS->Mat(Color, 1.0, 0.0, 0.0, 1.0, 1.0)\n")
    with pytest.raises(GrammarError, match=f"^{path}:1:15: error"):  # columns as an editor counts them
        load(path)


def test_a_subfolder_and_the_library_may_be_used(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "p.grammar").write_text("T->Skip(0)\n")
    (tmp_path / "main.grammar").write_text('use "parts/p.grammar" as P\nuse "brick.grammar" as B\nS->Skip(0)\n')
    grammar = load(tmp_path / "main.grammar")
    assert "P.T" in grammar.rules and any(name.startswith("B.") for name in grammar.rules)


def test_text_grammars_use_only_the_library(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "local.grammar").write_text("T->Skip(0)\n")
    with pytest.raises(GrammarError, match="not found"):
        loads('use "local.grammar" as L\nS->Skip(0)\n')
    assert any(name.startswith("B.") for name in loads('use "brick.grammar" as B\nS->Skip(0)\n').rules)


@pytest.mark.parametrize("breaker", ["\f", "\r"])
def test_odd_line_breaks_keep_the_caret_on_the_right_line(breaker):
    with pytest.raises(GrammarError) as info:
        loads(f"S->Skip(0){breaker}T->Skip(0)\nU->Skip(0 0)\n")
    text = str(info.value)
    assert "<string>:2:" in text and "U->Skip(0 0)" in text.splitlines()[1]
