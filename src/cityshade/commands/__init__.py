"""The `cityshade` command. Each command module adds its subcommands through a `register` function."""

from __future__ import annotations

import argparse
import contextlib
import importlib
import sys
import warnings

from .._files import signals_as_exit
from ..errors import CityshadeError, UsageError

# Modules that define `register(subparsers)`; each adds its own subcommands.
COMMAND_MODULES = (
    "cityshade.commands.render",
    "cityshade.commands.video",
    "cityshade.commands.tile",
    "cityshade.commands.view",
    "cityshade.commands.bench",
    "cityshade.commands.grammar",
    "cityshade.commands.compress",
    "cityshade.commands.info",
    "cityshade.commands.export",
    "cityshade.commands.serve",
    "cityshade.commands.dataset",
)


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a bad argument is one line (no usage block) and exit code 2."""

    def error(self, message: str):
        raise UsageError(f"{message}; see `{self.prog} --help`")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="cityshade", description="Render large virtual cities in real time.")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


@contextlib.contextmanager
def warnings_as_lines():
    """cityshade's own warnings (faces too narrow for their grammar, a style without relief) are one
    line each on stderr, like its errors, without the Python source line behind them; others, as
    Python shows them."""
    shown = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if category.__module__.split(".")[0] == "cityshade":
            print(f"cityshade: warning: {message}", file=sys.stderr if file is None else file)
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = shown


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        with signals_as_exit(), warnings_as_lines():
            args = parser.parse_args(argv)
            return int(args.run(args) or 0)
    except CityshadeError as exc:
        print(f"cityshade: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
