"""guess_missing: regional defaults, contradiction rules, small buildings, neighbours, flags, determinism."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from cityshade.maps import (
    BUILDING_ATTRIBUTES,
    TREE_ATTRIBUTES,
    MapBuilding,
    MapData,
    MapTree,
    building_masses,
    guess_missing,
    load_map,
)
from cityshade.scene import FLAGS

NUMERIC = ("height", "min_height", "levels", "min_level", "roof_height", "roof_levels", "roof_direction", "roof_angle")


def building(index=0, kind="yes", size=(20.0, 12.0), at=(0.0, 0.0), **tags) -> MapBuilding:
    x, y = at
    b = MapBuilding(index, f"way/{index}", shapely.box(x, y, x + size[0], y + size[1]), kind=kind)
    for name, value in tags.items():
        setattr(b, name, value)
        b.tagged.add(name)
    return b


def guessed(*buildings, trees=()) -> MapData:
    data = MapData(Path("test.osm"), (25.0, 60.0), "EPSG:32635", buildings=list(buildings), trees=list(trees))
    for i, b in enumerate(data.buildings):
        b.index = i
    data = guess_missing(data)
    return data


def rules(data: MapData) -> dict[str, int]:
    return {why: n for (what, why), n in data.report.repaired.items()}


# --------------------------------------------------------------------------- defaults per type


@pytest.mark.parametrize("kind", ["shed", "garage", "garages", "carport", "hut", "kiosk", "sauna", "cabin", "toilets"])
def test_utility_kinds_are_one_small_storey(kind):
    b = guessed(building(kind=kind, size=(8.0, 6.0))).buildings[0]
    assert b.levels == 1 and b.small_utility
    assert 2.0 < b.height < 5.0


def test_house_is_one_storey_and_an_attic_under_a_pitched_roof():
    b = guessed(building(kind="house", size=(11.0, 8.0))).buildings[0]
    assert b.roof_shape == "gabled" and b.levels == 1 and b.roof_levels == 1
    assert b.roof_height >= 2.2 and 5.0 < b.height < 7.5
    assert not b.small_utility


def test_flat_roofed_house_has_two_storeys():
    b = guessed(building(kind="detached", size=(11.0, 8.0), roof_shape="flat")).buildings[0]
    assert b.levels == 2 and b.roof_height == 0 and b.height == pytest.approx(6.0)


@pytest.mark.parametrize(
    "kind, levels, storey", [("apartments", 5, 3.0), ("office", 6, 3.5), ("retail", 2, 4.0), ("commercial", 4, 3.5)]
)
def test_storeys_and_storey_height_per_type(kind, levels, storey):
    b = guessed(building(kind=kind, size=(40.0, 15.0))).buildings[0]
    assert b.levels == levels and b.roof_shape == "flat"
    assert b.height == pytest.approx(levels * storey)


def test_unknown_kind_falls_back_to_a_generic_building():
    b = guessed(building(kind="spaceport", size=(30.0, 20.0))).buildings[0]
    assert b.levels == 3 and b.roof_shape == "flat"


@pytest.mark.parametrize("kind", ["yes", "residential"])
def test_untyped_footprints_by_size(kind):
    outbuilding, house, block = guessed(
        building(0, kind, size=(9.0, 5.0)),
        building(1, kind, size=(14.0, 10.0), at=(400.0, 0)),
        building(2, kind, size=(40.0, 14.0), at=(0, 400.0)),
    ).buildings
    assert outbuilding.levels == 1 and outbuilding.roof_shape == "gabled" and not outbuilding.small_utility
    assert house.levels == 1 and house.roof_levels == 1 and house.roof_shape == "gabled"
    assert block.levels >= 3 and block.roof_shape == "flat"


def test_a_small_part_is_not_a_house():
    part = building(0, "yes", size=(14.0, 10.0))
    part.is_part = True
    b = guessed(part).buildings[0]
    assert b.levels == 3 and b.roof_shape == "flat" and not b.small_utility


def test_levels_alone_give_the_height_and_height_alone_gives_the_levels():
    by_levels, by_height = guessed(
        building(0, "apartments", levels=8.0), building(1, "apartments", height=21.0)
    ).buildings
    assert by_levels.height == pytest.approx(24.0)
    assert by_height.levels == 7


def test_ridge_runs_along_the_long_side():
    """roof:direction is where the main face looks (OpenStreetMap): across the ridge."""
    east_west, north_south = guessed(
        building(0, "house", size=(12.0, 7.0)), building(1, "house", size=(7.0, 12.0), at=(500.0, 500.0))
    ).buildings
    assert east_west.roof_direction % 180.0 == pytest.approx(
        0.0
    ) and north_south.roof_direction % 180.0 == pytest.approx(90.0)


# --------------------------------------------------------------------------- flags


def test_every_attribute_is_tagged_or_guessed_and_tagged_values_are_kept():
    data = guessed(
        building(0, "apartments", levels=6.0, roof_shape="hipped"),
        building(1, "shed", size=(4.0, 3.0)),
        trees=[MapTree("node/1", (5.0, 5.0), genus="Pinus", tagged={"genus"})],
    )
    for b in data.buildings:
        for name in BUILDING_ATTRIBUTES:
            assert (name in b.tagged) != (name in b.guessed), name
            assert getattr(b, name) is not None, name
        for name in NUMERIC:
            assert getattr(b, name) is not None, name
    first = data.buildings[0]
    assert first.levels == 6 and first.roof_shape == "hipped" and first.tagged == {"levels", "roof_shape"}
    tree = data.trees[0]
    assert (
        tree.genus == "Pinus" and tree.leaf_type == "needleleaved" and tree.guessed == set(TREE_ATTRIBUTES) - {"genus"}
    )
    assert tree.height > 0 and tree.crown_diameter > 0


def test_tagged_and_guessed_counts_on_the_silent_map(silent_pbf):
    data = load_map(silent_pbf)
    tagged_levels = sum("levels" in b.tagged for b in data.buildings)
    data = guess_missing(data)
    count = len(data.buildings)
    assert sum("levels" in b.guessed for b in data.buildings) == count - tagged_levels
    assert sum("levels" in b.tagged for b in data.buildings) == tagged_levels
    assert sum("height" in b.guessed for b in data.buildings) == count  # no building there has a height tag
    small = [b for b in data.buildings if b.small_utility]
    assert small and all(b.levels == 1 for b in small)
    assert all("levels" not in b.tagged for b in small)


# --------------------------------------------------------------------------- contradictions


def test_levels_that_contradict_the_height_are_derived_from_the_height():
    data = guessed(building(levels=2.0, height=60.0))
    b = data.buildings[0]
    assert b.height == 60 and b.levels == round(60 / 3.2) and "levels" in b.guessed and "levels" not in b.tagged
    assert rules(data) == {"levels contradict height: levels derived from the height": 1}


def test_tall_storeys_of_a_church_are_no_contradiction():
    data = guessed(building(kind="church", levels=2.0, height=60.0))
    assert data.buildings[0].levels == 2 and not data.report.repaired


@pytest.mark.parametrize("name", ["levels", "height", "min_level", "min_height", "roof_height", "roof_levels"])
def test_values_below_zero_are_ignored(name):
    data = guessed(building(**{name: -3.0}))
    b = data.buildings[0]
    assert getattr(b, name) >= 0 and name in b.guessed
    assert rules(data) == {f"{name} below zero or not a number: ignored": 1}


def test_min_level_not_below_levels_counts_levels_from_min_level():
    data = guessed(building(levels=2.0, min_level=3.0))
    b = data.buildings[0]
    assert b.min_level == 3 and b.levels == 5 and b.height > b.min_height >= 0
    assert rules(data) == {"min_level not below levels: levels read as counted from min_level": 1}


def test_height_not_above_min_height_is_measured_from_min_height():
    data = guessed(building(height=10.0, min_height=12.0))
    b = data.buildings[0]
    assert b.min_height == 12 and b.height == 22
    assert rules(data) == {"height not above min_height: read as measured from min_height": 1}


def test_roof_above_the_building_is_cut_to_the_building():
    data = guessed(building(height=8.0, roof_height=30.0, roof_shape="gabled"))
    b = data.buildings[0]
    assert b.roof_height == 8 and b.height == 8
    assert rules(data) == {"roof_height above the building: cut to the building's height": 1}


@settings(max_examples=60, deadline=None)
@given(
    st.dictionaries(
        st.sampled_from(["height", "min_height", "levels", "min_level", "roof_height", "roof_levels"]),
        st.one_of(st.floats(-50, 300), st.just(float("nan"))),
    ),
    st.sampled_from(["yes", "house", "shed", "church", "roof", "apartments"]),
)
def test_never_a_negative_size(tags, kind):
    b = guessed(building(kind=kind, **tags)).buildings[0]
    assert 0 <= b.min_height < b.height
    assert 0 <= b.roof_height <= b.height - b.min_height
    assert 0 <= b.min_level < b.levels


# --------------------------------------------------------------------------- small buildings and neighbours


def test_small_footprints_are_one_storey_utility_buildings():
    tiny, tagged_tiny = guessed(
        building(0, "yes", size=(5.0, 4.0)), building(1, "yes", size=(5.0, 4.0), at=(300.0, 0.0), levels=2.0)
    ).buildings
    assert tiny.levels == 1 and tiny.small_utility and tiny.height < 5
    assert tagged_tiny.levels == 2 and not tagged_tiny.small_utility


def _neighbourhood(levels: float) -> list[MapBuilding]:
    """An untagged block in the middle of 24 tagged ones, 40 m apart."""
    blocks = [building(0, "yes", size=(25.0, 15.0))]
    for gx in range(-2, 3):
        for gy in range(-2, 3):
            if gx or gy:
                blocks.append(building(len(blocks), "yes", size=(25.0, 15.0), at=(40.0 * gx, 40.0 * gy), levels=levels))
    return blocks


def test_a_tall_tagged_neighbourhood_raises_the_guess():
    alone = guessed(building(0, "yes", size=(25.0, 15.0))).buildings[0]
    among_tall = guessed(*_neighbourhood(10.0)).buildings[0]
    among_low = guessed(*_neighbourhood(1.0)).buildings[0]
    assert among_low.levels < alone.levels < among_tall.levels
    assert among_tall.levels >= 7 and among_tall.height > 20


def test_tagged_roofs_nearby_choose_the_roof():
    houses = [building(0, "yes", size=(20.0, 14.0))]
    houses += [building(i, "yes", size=(20.0, 14.0), at=(30.0 * i, 0.0), roof_shape="hipped") for i in range(1, 7)]
    assert guessed(*houses).buildings[0].roof_shape == "hipped"
    assert guessed(building(0, "yes", size=(20.0, 14.0))).buildings[0].roof_shape == "flat"


def test_guesses_are_deterministic():
    first, second = guessed(*_neighbourhood(6.0)), guessed(*_neighbourhood(6.0))
    for a, b in zip(first.buildings, second.buildings):
        assert [getattr(a, n) for n in BUILDING_ATTRIBUTES] == [getattr(b, n) for n in BUILDING_ATTRIBUTES]


def test_regression_trained_on_the_map_beats_no_learning():
    """Buildings get taller toward the east; the model learns it from the tagged ones."""
    rng = np.random.default_rng(3)
    blocks = []
    for i in range(200):
        x = float(rng.uniform(0, 2000))
        levels = float(np.clip(round(1 + x / 250 + rng.normal(0, 0.5)), 1, 12))
        blocks.append(building(i, "yes", size=(20.0, 14.0), at=(x, float(rng.uniform(0, 400))), levels=levels))
    truth = [b.levels for b in blocks[:40]]
    for b in blocks[:40]:
        b.levels = None
        b.tagged.clear()
    data = guessed(*blocks)
    error = np.abs(np.array([b.levels for b in data.buildings[:40]]) - truth).mean()
    constant = np.abs(3 - np.array(truth)).mean()
    assert error < 0.5 * constant, (error, constant)


def test_info_counts_tagged_and_guessed_per_attribute(helsinki_pbf, capsys):
    """`cityshade info --json`: per attribute, the tagged and guessed counts add up to the buildings."""
    from cityshade.commands import main

    assert main(["info", str(helsinki_pbf), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    data = load_map(helsinki_pbf)
    tagged_levels = sum("levels" in b.tagged for b in data.buildings)
    counts = info["building_attributes"]
    for name in BUILDING_ATTRIBUTES:
        assert counts[name]["tagged"] + counts[name]["guessed"] == len(data.buildings), name
    data = guess_missing(data)
    assert counts["levels"]["tagged"] == sum("levels" in b.tagged for b in data.buildings)
    # Only the contradiction rules move a tagged value to the guesses.
    moved = sum(
        n
        for (what, why), n in data.report.repaired.items()
        if why.startswith("levels") or "levels read as counted" in why
    )
    assert counts["levels"]["tagged"] == tagged_levels - moved and counts["levels"]["tagged"] > 200


def test_a_dome_does_not_spread_to_the_ordinary_buildings_around():
    church = building(0, "church", size=(20.0, 20.0), roof_shape="dome")
    around = [building(i, "yes", size=(20.0, 14.0), at=(30.0 * i, 0.0)) for i in range(1, 4)]
    turret = building(4, "yes", size=(4.0, 4.0), at=(20.0, 20.0))  # shares a corner with the church
    turret.is_part = True
    data = guessed(church, *around, turret)
    assert [b.roof_shape for b in data.buildings[1:4]] == ["flat"] * 3
    assert data.buildings[4].roof_shape == "dome"


def test_guessing_twice_changes_nothing():
    data = guessed(
        *_neighbourhood(6.0),
        building(30, "yes", at=(900.0, 0.0), levels=2.0, height=60.0),
        building(31, "yes", at=(0.0, 900.0), height=10.0, min_height=12.0),
        building(32, "apartments", size=(40.0, 24.0), at=(900.0, 900.0), height=18.0, levels=6.0, roof_shape="gabled"),
        building(33, "yes", size=(30.0, 20.0), at=(-900.0, 0.0), levels=2.7, min_level=2.5),
    )
    gabled = data.buildings[-2]
    assert gabled.height - gabled.roof_height >= 6 * 2.5 and "roof_height" in gabled.guessed
    before = [[getattr(b, n) for n in NUMERIC + BUILDING_ATTRIBUTES] for b in data.buildings]
    repairs = dict(data.report.repaired)
    data = guess_missing(data)
    assert [[getattr(b, n) for n in NUMERIC + BUILDING_ATTRIBUTES] for b in data.buildings] == before
    assert dict(data.report.repaired) == repairs


def test_buildings_thousands_of_kilometres_apart_take_bounded_memory():
    """The neighbourhood grids grow with the extract's width; far-apart buildings (a file mixing
    places, found by the GeoJSON fuzzer) once asked for 40 GiB. Now the grid coarsens instead."""
    import resource

    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    data = guessed(building(0, "house", levels=2.0), building(1, "house", at=(3_000_000.0, 1_200_000.0)))
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    assert all(b.levels >= 1 for b in data.buildings)
    assert grown_mb < 500, f"{grown_mb:.0f} MB"


def test_a_tiny_shed_gets_no_interior_and_a_house_keeps_its_rooms():
    data = guessed(building(0, "shed", size=(4.0, 3.0)), building(1, "house", size=(12.0, 9.0), at=(20.0, 0.0)))
    shed, house = building_masses(data)
    assert shed.flags & FLAGS["FLAG_NO_INTERIOR"] and not shed.interior
    assert not house.flags & FLAGS["FLAG_NO_INTERIOR"] and house.interior


def test_map_city_leaves_the_map_as_read():
    """Guessing fills a copy: the map read stays as it was, so it can be laid out again or compared."""
    import copy

    from cityshade.maps import load_map, map_city

    data = load_map(Path(__file__).parents[1] / "data" / "maps" / "entrances.osm")
    as_read = copy.deepcopy(data)
    city = map_city(data)
    assert len(city.masses) and data == as_read
    assert all(building.height is None or "height" in building.tagged for building in data.buildings)
