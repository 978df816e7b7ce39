"""Urban form and the guessing model: forms named on hand-made footprints, determinism, the prior file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import PRIOR_FILE, MapBuilding, MapData, guess_missing, load_prior, prior_bytes, train_prior
from cityshade.maps.testing import FORM_FEATURES, training_rows, urban_form


def _map(*buildings: MapBuilding) -> MapData:
    for i, b in enumerate(buildings):
        b.index = i
    return MapData(Path("form.osm"), (25.0, 60.0), "EPSG:32635", buildings=list(buildings))


def _box(x0, y0, x1, y1, kind="yes", **tags) -> MapBuilding:
    b = MapBuilding(0, f"way/{x0}-{y0}", shapely.box(x0, y0, x1, y1), kind=kind)
    for name, value in tags.items():
        setattr(b, name, value)
        b.tagged.add(name)
    return b


def _terrace(units=4, at=(0.0, 0.0)) -> list[MapBuilding]:
    """Row houses 6 m wide and 10 m deep on one line, each pair sharing the nodes of its party wall."""
    x, y = at
    return [_box(x + 6.0 * k, y, x + 6.0 * (k + 1), y + 10.0, kind="house") for k in range(units)]


def _column(form, name):
    return form.values[:, FORM_FEATURES.index(name)]


def test_a_terrace_of_four_row_houses_is_recognised_and_guessed_low_and_pitched():
    data = _map(*_terrace())
    form = urban_form(data)
    assert list(form.forms) == ["terrace_house"] * 4
    assert list(_column(form, "touching")) == [1, 2, 2, 1]
    assert list(_column(form, "block_buildings")) == [4] * 4
    shared = _column(form, "shared_wall_share")
    assert shared[1] == pytest.approx(20 / 32) and shared[0] == pytest.approx(10 / 32)  # 10 m walls of 32 m
    guessed = guess_missing(data)
    assert all(b.levels <= 2 and b.roof_shape != "flat" and b.form == "terrace_house" for b in guessed.buildings)


def test_a_long_shallow_outline_alone_is_a_row_house_of_one_storey():
    guessed = guess_missing(_map(_box(0, 0, 42, 10, kind="residential"), _box(0, 40, 40, 55, kind="residential")))
    row, block = guessed.buildings
    assert row.form == "row_house" and row.levels == 1 and row.roof_shape == "gabled"
    assert block.form == ""  # 15 m deep: a block of flats, not a row house


def test_two_houses_sharing_a_wall_are_semi_detached():
    form = urban_form(_map(*_terrace(units=2)))
    assert list(form.forms) == ["semi_detached"] * 2


def test_a_shed_is_one_small_storey_and_a_garage_keeps_its_flat_roof():
    guessed = guess_missing(_map(_box(0, 0, 5, 4), _box(20, 0, 26, 4, kind="garage"), _box(40, 0, 60, 12)))
    shed, garage, house = guessed.buildings
    assert shed.form == "shed" and shed.levels == 1 and shed.small_utility
    assert garage.levels == 1 and garage.roof_shape == "flat" and garage.small_utility
    assert house.form == "" and not house.small_utility


def test_a_compact_small_part_of_a_building_of_parts_is_a_tower():
    church = _box(0, 0, 40, 20, kind="church")
    church.replaced_by_parts = True
    nave, tower, choir = _box(0, 0, 30, 20), _box(30, 5, 38, 13), _box(30, 0, 40, 5)
    for part in (nave, tower, choir):
        part.is_part, part.parent = True, 0
    form = urban_form(_map(church, nave, tower, choir))
    assert list(form.forms) == ["", "", "tower", ""]  # the choir strip is not compact
    assert list(_column(form, "parts")) == [3, 3, 3, 3]


def test_neighbour_rings_count_within_50_and_100_m():
    data = _map(_box(0, 0, 10, 10), _box(40, 0, 50, 10), _box(90, 0, 100, 10), _box(300, 0, 310, 10))
    form = urban_form(data)
    assert list(_column(form, "count_50")) == [1, 1, 0, 0]  # centres 40, 50 (not within) and 210 m apart
    assert list(_column(form, "count_100")) == [2, 2, 2, 0]
    assert _column(form, "nearest_m")[:3] == pytest.approx([30, 30, 40])
    assert np.isnan(_column(form, "nearest_m")[3])  # nothing within 100 m


def test_guesses_carry_a_confidence_and_tagged_values_none():
    data = _map(_box(0, 0, 20, 12, levels=3.0), _box(30, 0, 50, 12))
    tagged, silent = guess_missing(data).buildings
    assert "levels" not in tagged.confidence
    assert set(silent.confidence) == {"levels", "height", "roof_shape"}
    assert all(0.0 <= v <= 1.0 for v in silent.confidence.values())


def test_guessing_is_deterministic_with_trees_grown_on_the_map():
    buildings = [_box(30.0 * i, 0, 30.0 * i + 20, 14, levels=float(2 + i % 5)) for i in range(12)]
    buildings += [_box(30.0 * i, 40, 30.0 * i + 20, 54) for i in range(6)]
    first, second = guess_missing(_map(*buildings)), guess_missing(_map(*buildings))
    assert [b.levels for b in first.buildings] == [b.levels for b in second.buildings]
    assert [b.confidence for b in first.buildings] == [b.confidence for b in second.buildings]


def test_the_prior_trains_to_the_same_bytes_and_holds_a_leave_one_out_set_per_city():
    def city(x):
        roofs = ("flat", "gabled")
        return _map(
            *[
                _box(x + 30.0 * i, 0, x + 30.0 * i + 20, 14, levels=float(1 + i % 4), roof_shape=roofs[i % 2])
                for i in range(10)
            ]
        )

    maps = {"east": city(0.0), "west": city(1000.0)}
    document = train_prior(maps)
    assert sorted(document["models"]) == ["all", "without east", "without west"]
    assert prior_bytes(document) == prior_bytes(train_prior(maps))
    rows = training_rows(maps["east"], "east")
    assert len(rows.x) == 20 and np.isfinite(rows.levels).all()  # each building in a fold and silent


def test_the_shipped_prior_is_small_and_loads():
    assert PRIOR_FILE.stat().st_size < 1_000_000
    prior = load_prior()
    assert prior.name == "all cities" and {"Helsinki", "Andorra", "Monaco"} <= set(prior.cities)
    assert load_prior(without="Helsinki").name == "without Helsinki"
