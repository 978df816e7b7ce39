"""`cityshade bench guesses [--map FILE]`: how far the guessing model is from what a map says, by k-fold.

The tagged buildings of the map (the Helsinki extract by default) are split into FOLDS groups (fixed
seed; the same folds for every guesser). For each group every size and roof tag of its buildings is
hidden (height, min_height, levels, min_level, roof height, roof levels and roof shape: the building
becomes as silent as most of OpenStreetMap), the guessers run on the whole map, and their guesses are
compared with the hidden values. Side by side:

- model: `guess_missing`, learning from the other groups' tags and the shipped prior. Where the map is
  one of the prior's training cities, the prior trained without that city is used (leave one city out);
- model_silent: the same on the map with every tag hidden (what a map that tags nothing gets);
- defaults: the regional defaults of each building's type, size and form alone;
- median: the median levels and height of the other groups and their most common roof (the fairest constant);
- constant_10m: 10 m of 3.2 m storeys under a flat roof (what cityshade drew before guessing).

Also: the model's mean confidence beside how often it was right (calibration), and the time to guess
100,000 buildings (the map's buildings tiled side by side).
"""

from __future__ import annotations

import copy
import dataclasses
import time
from pathlib import Path

import numpy as np
import shapely

from ..errors import UsageError
from ..maps import ReadReport, guess_missing, hide_sizes, load_map, load_prior, prior_city
from ._harness import BenchResult

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
FOLDS = 5
SEED = 17
OLD_HEIGHT, OLD_STOREY = 10.0, 3.2  # every building before guessing: 10 m of 3.2 m storeys
GUESSERS = ("model", "model_silent", "defaults", "median", "constant_10m")
BASELINES = ("defaults", "median", "constant_10m")
# ratio -> (error key, whether smaller is better)
MEASURES = {
    "levels_mae": ("levels", True),
    "height_mae_m": ("height", True),
    "roof_shape_accuracy": ("roof", False),
    "flat_vs_pitched_accuracy": ("flat", False),
}
TARGETS = {"levels_mae": 1.0, "height_mae_m": 3.0, "flat_vs_pitched_accuracy": 0.9}


def _truth(map_data):
    """Tagged levels, heights and roof shapes by building index (before any guessing)."""
    levels = {b.index: b.levels for b in map_data.buildings if "levels" in b.tagged}
    heights = {b.index: b.height for b in map_data.buildings if "height" in b.tagged}
    roofs = {b.index: b.roof_shape for b in map_data.buildings if "roof_shape" in b.tagged}
    return levels, heights, roofs


def _hidden(map_data, held):
    hidden = copy.deepcopy(map_data)
    for i in held:
        hide_sizes(hidden.buildings[i])
    return hidden


def evaluate(map_data, folds: int = FOLDS, seed: int = SEED, prior=None) -> dict:
    """Errors of the model and the baselines over `folds` folds, the model's calibration and the counts."""
    levels, heights, roofs = _truth(map_data)
    evaluated = sorted(set(levels) | set(heights) | set(roofs))
    if len(evaluated) < folds:
        raise UsageError(
            f"{map_data.source}: only {len(evaluated)} buildings with a tagged size or roof; "
            f"need at least {folds} to measure the guesses"
        )
    order = np.random.default_rng(seed).permutation(evaluated)
    errors = {name: {"levels": [], "height": [], "roof": [], "flat": []} for name in GUESSERS}
    calibration = {"levels": [], "height": [], "roof_shape": []}  # (confidence, right) of the model's guesses
    silent = guess_missing(_hidden(map_data, evaluated), prior=prior)
    defaults = guess_missing(_hidden(map_data, evaluated), learn=False)
    for fold in np.array_split(order, folds):
        held = sorted(int(i) for i in fold)
        guessed = guess_missing(_hidden(map_data, held), prior=prior)
        train_levels = [v for i, v in levels.items() if i not in held]
        train_heights = [v for i, v in heights.items() if i not in held]
        train_roofs = [v for i, v in roofs.items() if i not in held]
        median = (
            float(np.median(train_levels)) if train_levels else OLD_HEIGHT / OLD_STOREY,
            float(np.median(train_heights)) if train_heights else OLD_HEIGHT,
            max(sorted(set(train_roofs)), key=train_roofs.count) if train_roofs else "flat",
        )
        truth = (levels, heights, roofs)
        for i in held:
            for name, source in (("model", guessed), ("model_silent", silent), ("defaults", defaults)):
                b = source.buildings[i]
                _score(errors[name], i, truth, b.levels, b.height, b.roof_shape)
            _score(errors["median"], i, truth, *median)
            _score(errors["constant_10m"], i, truth, OLD_HEIGHT / OLD_STOREY, OLD_HEIGHT, "flat")
            _calibrate(calibration, guessed.buildings[i], i, truth)
    scores = {
        name: {ratio: float(np.mean(e[key])) if e[key] else float("nan") for ratio, (key, _) in MEASURES.items()}
        for name, e in errors.items()
    }
    counts = {"levels": len(levels), "height": len(heights), "roof_shape": len(roofs), "folds": folds}
    return scores | {"calibration": calibration, "counts": counts}


def _score(into, i, truth, guess_levels, guess_height, guess_roof):
    levels, heights, roofs = truth
    if i in levels:
        into["levels"].append(abs(guess_levels - levels[i]))
    if i in heights:
        into["height"].append(abs(guess_height - heights[i]))
    if i in roofs:
        into["roof"].append(guess_roof == roofs[i])
        into["flat"].append((guess_roof == "flat") == (roofs[i] == "flat"))


def _calibrate(into, building, i, truth):
    levels, heights, roofs = truth
    confidence = building.confidence
    if i in levels and "levels" in confidence:
        into["levels"].append((confidence["levels"], abs(building.levels - levels[i]) <= 1.0))
    if i in heights and "height" in confidence:
        into["height"].append((confidence["height"], abs(building.height - heights[i]) <= 3.0))
    if i in roofs and "roof_shape" in confidence:
        into["roof_shape"].append((confidence["roof_shape"], (building.roof_shape == "flat") == (roofs[i] == "flat")))


def tiled(map_data, count: int):
    """The map's buildings repeated side by side (50 m apart) until there are `count` of them."""
    x0, y0, x1, y1 = map_data.bounds()
    source = map_data.buildings
    copies = -(-count // len(source))
    across = int(np.ceil(np.sqrt(copies)))
    outlines = np.array([b.outline for b in source], dtype=object)
    buildings = []
    for k in range(copies):
        shift = np.array([(k % across) * (x1 - x0 + 50.0), (k // across) * (y1 - y0 + 50.0)])
        offset = k * len(source)
        for b, outline in zip(source, shapely.transform(outlines, lambda c, shift=shift: c + shift)):
            parent = None if b.parent is None else b.parent + offset
            buildings.append(
                dataclasses.replace(
                    b,
                    index=len(buildings),
                    outline=outline,
                    parent=parent if parent is not None and parent < count else None,
                    tagged=set(b.tagged),
                    guessed=set(b.guessed),
                    confidence={},
                    beneath_parts=[(under, part.index + offset) for under, part in b.beneath_parts],
                )
            )
    buildings = buildings[:count]
    for b in buildings:  # the copies' parts, where the copy kept them
        b.beneath_parts = [(under, buildings[i]) for under, i in b.beneath_parts if i < count]
    return dataclasses.replace(map_data, buildings=buildings, trees=[], report=ReadReport())


def _prior_for(map_data):
    """The prior to measure `map_data` with: without the map's own city where the prior was trained on it."""
    city = prior_city(map_data)
    if city is None:
        return load_prior(), "the shipped prior (not trained on this map)"
    return load_prior(without=city), f"the prior trained without {city} (this map is in {city}: left out)"


def _table_rows(scores):
    return [[name] + [round(scores[name][ratio], 3) for ratio in MEASURES] for name in GUESSERS]


def _calibration_rows(calibration):
    rows = []
    for name, pairs in calibration.items():
        if pairs:
            confidence, right = np.array(pairs, float).T
            rows.append([name, len(pairs), round(float(confidence.mean()), 3), round(float(right.mean()), 3)])
    return rows


def run(quick: bool, out_dir: Path, map_path: Path | None = None) -> BenchResult:
    path = Path(map_path) if map_path is not None else HELSINKI
    if not path.exists():
        hint = "run `make data` to fetch the Helsinki extract" if map_path is None else "check the path"
        raise UsageError(f"{path}: missing; {hint}")
    map_data = load_map(path)
    prior, prior_note = _prior_for(map_data)
    scores = evaluate(map_data, prior=prior)
    counts, calibration = scores.pop("counts"), scores.pop("calibration")
    result = BenchResult("guesses", "cpu")
    result.add_table(
        f"{path.name}, {counts['folds']}-fold (seed {SEED}): {counts['levels']} tagged levels, "
        f"{counts['height']} tagged heights, {counts['roof_shape']} tagged roof shapes",
        ["guesser", "levels MAE (storeys)", "height MAE (m)", "roof shape right", "flat vs pitched right"],
        _table_rows(scores),
    )
    result.add_table(
        "calibration of the model's confidence (levels within one storey, height within 3 m, flat or pitched)",
        ["value", "guesses", "mean confidence", "share right"],
        _calibration_rows(calibration),
    )
    result.ratios = {ratio: scores["model"][ratio] for ratio in MEASURES}
    for name in GUESSERS[1:]:
        result.ratios |= {f"{name}_{ratio}": scores[name][ratio] for ratio in MEASURES}
    for ratio, (_, smaller) in MEASURES.items():
        values = [scores[name][ratio] for name in BASELINES if np.isfinite(scores[name][ratio])]
        if values:
            result.ratios[f"best_baseline_{ratio}"] = min(values) if smaller else max(values)
    result.targets = {
        ratio: f"{'<=' if ratio != 'flat_vs_pitched_accuracy' else '>='} {v}" for ratio, v in TARGETS.items()
    }
    result.targets["roof_shape_accuracy"] = "> best baseline"
    many = tiled(map_data, 20_000 if quick else 100_000)
    start, cpu = time.perf_counter(), time.process_time()
    many = guess_missing(many)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    speed = f"guess_{len(many.buildings) // 1000}k"
    result.ratios[f"{speed}_seconds"] = seconds
    result.ratios[f"{speed}_cpu_seconds"] = cpu
    result.targets[f"{speed}_seconds"] = "< 5 (100k)"
    result.notes.append(f"Prior: {prior_note}.")
    result.notes.append(
        f"{speed}_seconds (wall) and _cpu_seconds (this process): guess_missing on the {path.name} buildings "
        f"tiled to {len(many.buildings):,} (100,000 without --quick, 20,000 with)."
    )
    result.notes.append("Map data © OpenStreetMap contributors, ODbL 1.0.")
    return result
