"""`cityshade grammar check FILE...` and `cityshade grammar render FILE ...`."""

from __future__ import annotations

import sys
from pathlib import Path

from ._diagnostics import GrammarError


def register(subparsers):
    parser = subparsers.add_parser("grammar", help="check or render facade grammar files")
    commands = parser.add_subparsers(dest="grammar_command", required=True, metavar="ACTION")
    check = commands.add_parser("check", help="check grammar files; errors as FILE:LINE:COL: error: ...")
    check.add_argument("files", nargs="+", type=Path, metavar="FILE")
    check.set_defaults(run=_check)


def _check(args) -> int:
    from . import compile_grammars, load

    failed = False
    for path in args.files:
        try:
            grammar = load(path)
            compiled = compile_grammars({str(path): grammar})
        except GrammarError as exc:
            print(str(exc), file=sys.stderr)
            failed = True
            continue
        print(f"{path}: ok, {len(grammar.rules)} rules, {compiled.used} texels ({compiled.nbytes} bytes), "
              f"start rule {grammar.start}")
    return 1 if failed else 0
