"""Command-line flags read from a settings dataclass: each field whose metadata holds a "flag"
(cityshade.frame.CommandFlag) is offered by the commands that choose it, under that flag's name and
help. A flag's value sits in the parsed arguments under its field's name, as typed (--time stays
HH:MM, which a map's sun also reads), until `settings_from_flags` parses it."""

from __future__ import annotations

import argparse
import dataclasses


def _flags(settings: type) -> dict:
    """{field name: CommandFlag} of the fields of `settings` that have a flag."""
    return {f.name: f.metadata["flag"] for f in dataclasses.fields(settings) if "flag" in f.metadata}


def add_settings_flags(parser, settings: type, names, **changes: dict):
    """Adds the flags of the `settings` fields `names`, in that order. `changes` give a field's flag
    another default or help in this command (field name -> {"default": ..., "help": ...})."""
    flags, defaults = _flags(settings), {f.name: f.default for f in dataclasses.fields(settings)}
    for name in names:
        flag = flags[name]
        options = {"dest": name, "default": defaults[name], "help": flag.help}
        if isinstance(defaults[name], bool):
            switch_off = flag.name.startswith("--no-")
            options["action"] = "store_false" if switch_off else argparse.BooleanOptionalAction
        elif flag.choices:
            options.update(type=type(flag.choices[0]), choices=flag.choices)
        else:
            options["metavar"] = flag.name.removeprefix("--").upper()
        if flag.typed_default is not None:
            options["default"] = flag.typed_default
        parser.add_argument(flag.name, **{**options, **changes.pop(name, {})})
    if changes:
        raise ValueError(f"no flag chosen for {', '.join(changes)}")


def settings_from_flags(args, settings: type) -> dict:
    """The keyword arguments of `settings` that the parsed `args` give: each of its flags the
    command offers, parsed (bad text raises the parser's UsageError)."""
    given = vars(args)
    return {
        name: flag.parse(given[name]) if flag.parse else given[name]
        for name, flag in _flags(settings).items()
        if name in given
    }
