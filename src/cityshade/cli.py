"""The `cityshade` command. Each technique adds its subcommands through a `register` function."""

from __future__ import annotations

import argparse
import importlib
import sys

from .errors import CityshadeError

# Modules that define `register(subparsers)`; each adds its own subcommands.
COMMAND_MODULES = (
    "cityshade.render._cli",
    "cityshade.render._video",
    "cityshade.viewer",
    "cityshade.bench._cli",
    "cityshade.grammar._cli",
    "cityshade.relief._cli",
    "cityshade.maps._info",
    "cityshade.export._cli",
    "cityshade.dataset._cli",
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="cityshade", description="Render large virtual cities in real time.")
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except CityshadeError as exc:
        print(f"cityshade: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
