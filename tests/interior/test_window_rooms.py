"""Every window opens onto exactly one room: over the built-in district's and the Helsinki
extract's viewpoints, no window's glass shows two room ids in the id AOV (the numbers
`cityshade bench facades` reports as windows_straddling_rooms_district and _osm)."""

from __future__ import annotations

from cityshade.bench.facades import straddling_windows
from cityshade.maps import load_map, map_city
from cityshade.scene import make_city

SIZE = (480, 270)


def _check(counts: dict[str, int], name: str):
    print(f"{name}: {counts}")
    assert counts["windows"] > 1000
    assert counts["straddling"] == 0, f"{counts['straddling']} windows show more than one room"
    # glass patches showing several rooms are windows that touch on the screen, each with its own room
    assert counts["patches_with_rooms"] == counts["patches_of_touching_windows"]


def test_no_window_of_the_district_shows_two_rooms(gl_context):
    _check(straddling_windows(gl_context, make_city("default"), SIZE), "district")


def test_no_window_of_helsinki_shows_two_rooms(gl_context, helsinki_pbf):
    _check(straddling_windows(gl_context, map_city(load_map(helsinki_pbf)), SIZE), "Helsinki")
