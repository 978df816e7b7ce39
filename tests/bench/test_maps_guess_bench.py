"""bench guesses: the k-fold hides what it scores, scores the baselines exactly, and leaves the map alone."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely

from cityshade.bench.guesses import evaluate, tiled
from cityshade.errors import UsageError
from cityshade.maps import MapBuilding, MapData


def _street(levels=(2.0, 4.0, 6.0, 8.0, 4.0, 6.0, 2.0, 8.0, 4.0, 6.0)) -> MapData:
    buildings = []
    for i, value in enumerate(levels):
        b = MapBuilding(
            i,
            f"way/{i}",
            shapely.box(30.0 * i, 0, 30.0 * i + 20, 15),
            levels=value,
            roof_shape="hipped",
            tagged={"levels", "roof_shape"},
        )
        buildings.append(b)
    buildings.append(MapBuilding(len(levels), "way/99", shapely.box(0, 100, 20, 115)))
    return MapData(Path("street.osm"), (25.0, 60.0), "EPSG:32635", buildings=buildings)


def test_baselines_are_scored_exactly_and_the_map_is_untouched():
    data = _street()
    scores = evaluate(data, folds=5, seed=1)
    levels = [2.0, 4.0, 6.0, 8.0, 4.0, 6.0, 2.0, 8.0, 4.0, 6.0]
    assert scores["constant_10m"]["levels_mae"] == pytest.approx(sum(abs(10 / 3.2 - v) for v in levels) / 10)
    assert scores["constant_10m"]["roof_shape_accuracy"] == 0.0  # always flat, every tagged roof hipped
    assert scores["median"]["roof_shape_accuracy"] == 1.0
    assert scores["counts"] == {"levels": 10, "height": 0, "roof_shape": 10, "folds": 5}
    # The hidden roofs are found again from the tagged ones nearby.
    assert scores["model"]["roof_shape_accuracy"] == 1.0
    assert all(b.guessed == set() and b.tagged == {"levels", "roof_shape"} for b in data.buildings[:10])
    assert data.buildings[10].levels is None


def test_too_few_tagged_buildings_is_one_clear_error():
    with pytest.raises(UsageError, match="need at least 5"):
        evaluate(_street(levels=(3.0, 4.0)), folds=5)


def test_tiling_repeats_the_buildings_side_by_side():
    data = _street()
    many = tiled(data, 25)
    assert len(many.buildings) == 25 and [b.index for b in many.buildings] == list(range(25))
    assert many.buildings[11].levels == data.buildings[0].levels
    assert not many.buildings[11].outline.intersects(data.buildings[0].outline)


def test_flat_and_pitched_are_scored_and_the_confidence_is_kept_beside_the_truth():
    data = _street()
    for b in data.buildings[:10:2]:
        b.roof_shape = "flat"  # every other roof flat: a shape can be wrong while flat-or-pitched is right
    scores = evaluate(data, folds=5, seed=1)
    assert set(scores) == {"model", "model_silent", "defaults", "median", "constant_10m", "calibration", "counts"}
    assert scores["constant_10m"]["flat_vs_pitched_accuracy"] == 0.5
    assert scores["median"]["flat_vs_pitched_accuracy"] == pytest.approx(scores["median"]["roof_shape_accuracy"])
    pairs = scores["calibration"]["levels"]
    assert len(pairs) == 10 and all(0.0 <= c <= 1.0 and isinstance(right, bool) for c, right in pairs)


def test_only_bench_guesses_takes_a_map(capsys):
    from cityshade.commands import main

    assert main(["bench", "trees", "--map", "street.osm"]) == 2
    assert "only `bench guesses` measures a map" in capsys.readouterr().err
