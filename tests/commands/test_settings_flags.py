"""The RenderSettings flags of render, view and video come from one declaration, the fields'
metadata, and each round-trips from the command line into its field."""

from __future__ import annotations

import argparse
import dataclasses

import pytest

from cityshade.commands import OneLineParser, build_parser
from cityshade.commands.settings_flags import add_settings_flags, settings_from_flags
from cityshade.errors import UsageError
from cityshade.frame import CommandFlag, RenderSettings

FLAGGED = [f.name for f in dataclasses.fields(RenderSettings) if "flag" in f.metadata]

# field -> (command line, the field's value from it); every flagged field needs one
GIVEN = {
    "interior_mapping": (["--no-interiors"], False),
    "relief": (["--no-relief"], False),
    "building_lod": (["--building-lod"], True),
    "samples": (["--samples", "8"], 8),
    "lights": (["--lights", "0.25"], 0.25),
    "time_of_day": (["--time", "06:30"], 6.5),
    "grammar_cache": (["--grammar-cache"], True),
}

# each command's settings flags, as the command line has always had them
OFFERED = {
    "render": {"lights", "time_of_day", "interior_mapping", "relief", "samples", "building_lod", "grammar_cache"},
    "view": {"time_of_day", "samples", "building_lod", "grammar_cache"},
    "video": {"time_of_day"},
}


def _subparser(command: str) -> argparse.ArgumentParser:
    subparsers = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return subparsers.choices[command]


def test_every_flagged_field_round_trips():
    assert sorted(GIVEN) == sorted(FLAGGED)
    parser = OneLineParser(prog="test")
    add_settings_flags(parser, RenderSettings, FLAGGED)
    for name, (argv, value) in GIVEN.items():
        settings = RenderSettings(**settings_from_flags(parser.parse_args(argv), RenderSettings))
        assert getattr(settings, name) == value, argv
        assert getattr(settings, name) != getattr(RenderSettings(), name), argv  # the flag changed it


def test_unflagged_defaults_give_the_default_settings():
    parser = OneLineParser(prog="test")
    add_settings_flags(parser, RenderSettings, FLAGGED)
    settings = RenderSettings(**settings_from_flags(parser.parse_args([]), RenderSettings))
    assert settings == RenderSettings(time_of_day=19 + 10 / 60)  # --time's default is 19:10 as typed


def test_a_bad_flag_text_is_the_parsers_one_line():
    parser = OneLineParser(prog="test")
    add_settings_flags(parser, RenderSettings, ["time_of_day", "lights"])
    with pytest.raises(UsageError, match=r"invalid time '25:00'"):
        settings_from_flags(parser.parse_args(["--time", "25:00"]), RenderSettings)
    with pytest.raises(UsageError, match=r"invalid --lights '2'"):
        settings_from_flags(parser.parse_args(["--lights", "2"]), RenderSettings)


@pytest.mark.parametrize("command", sorted(OFFERED))
def test_each_commands_settings_flags_are_the_declared_ones(command):
    declared = {f.name: f.metadata["flag"] for f in dataclasses.fields(RenderSettings) if "flag" in f.metadata}
    actions = {a.dest: a for a in _subparser(command)._actions if a.dest in declared}
    assert set(actions) == OFFERED[command]
    for name, action in actions.items():
        assert action.option_strings[0] == declared[name].name


def test_a_command_may_change_a_flags_default_and_help():
    render, view, video = (_subparser(c) for c in ("render", "view", "video"))
    assert render.parse_args([]).samples == RenderSettings.samples == 4
    assert view.parse_args([]).samples == 0  # the viewer starts without MSAA (M toggles it)
    helps = {
        c: next(a.help for a in p._actions if a.dest == "time_of_day") for c, p in zip("rvV", (render, view, video))
    }
    assert helps["r"] == helps["v"] == "time of day HH:MM (sun, sky, lit rooms)"
    assert helps["V"] == "time of day at the start, HH:MM"


def test_metadata_on_a_field_makes_its_flag():
    @dataclasses.dataclass(frozen=True)
    class Synthetic:
        width: int = dataclasses.field(default=3, metadata={"flag": CommandFlag("--width", "how wide", parse=int)})
        fog: bool = dataclasses.field(default=True, metadata={"flag": CommandFlag("--no-fog", "clear air")})
        unflagged: float = 1.0

    parser = OneLineParser(prog="test")
    add_settings_flags(parser, Synthetic, ["width", "fog"])
    assert "--width WIDTH  how wide" in parser.format_help() and "--no-fog" in parser.format_help()
    assert Synthetic(**settings_from_flags(parser.parse_args(["--width", "7", "--no-fog"]), Synthetic)) == Synthetic(
        width=7, fog=False
    )
    with pytest.raises(KeyError):
        add_settings_flags(OneLineParser(prog="test"), Synthetic, ["unflagged"])


def test_a_change_to_a_flag_not_chosen_is_refused():
    with pytest.raises(ValueError, match="no flag chosen for samples"):
        add_settings_flags(OneLineParser(prog="test"), RenderSettings, ["time_of_day"], samples={"default": 0})
