"""`cityshade bench guesses`: how far the guessing model is from what the map says, by k-fold.

The tagged buildings of the Helsinki extract are split into FOLDS groups (fixed seed). For each group
every size and roof tag of its buildings is hidden (height, min_height, levels, min_level, roof height,
roof levels and roof shape: the building becomes as silent as most of OpenStreetMap), `guess_missing`
runs on the whole map, and the guesses are compared with the hidden values. Side by side: the regional
defaults alone (nothing tagged to learn from), a constant 10 m (what cityshade drew before guessing),
and the constant median of the other groups (the fairest constant); for roofs, always flat.
"""

from __future__ import annotations

import copy
import dataclasses
import time
from pathlib import Path

import numpy as np
import shapely

from ..errors import UsageError
from ..maps import ReadReport, guess_missing, load_map
from ._harness import BenchResult

HELSINKI = Path(__file__).resolve().parents[3] / "data" / "Helsinki.osm.pbf"
FOLDS = 5
SEED = 17
HIDDEN = ("height", "min_height", "levels", "min_level", "roof_shape", "roof_height", "roof_levels")
OLD_HEIGHT, OLD_STOREY = 10.0, 3.2  # every building before guessing: 10 m of 3.2 m storeys


def _hide(building):
    for name in HIDDEN:
        if name in building.tagged:
            setattr(building, name, None)
            building.tagged.discard(name)


def _truth(map_data):
    """Tagged levels, heights and roof shapes by building index (before any guessing)."""
    levels = {b.index: b.levels for b in map_data.buildings if "levels" in b.tagged}
    heights = {b.index: b.height for b in map_data.buildings if "height" in b.tagged}
    roofs = {b.index: b.roof_shape for b in map_data.buildings if "roof_shape" in b.tagged}
    return levels, heights, roofs


def evaluate(map_data, folds: int = FOLDS, seed: int = SEED) -> dict:
    """Mean absolute errors and roof accuracy of the model and the baselines over `folds` folds."""
    levels, heights, roofs = _truth(map_data)
    evaluated = sorted(set(levels) | set(heights) | set(roofs))
    if len(evaluated) < folds:
        raise UsageError(
            f"{map_data.source}: only {len(evaluated)} buildings with a tagged size or roof; "
            f"need at least {folds} to measure the guesses"
        )
    order = np.random.default_rng(seed).permutation(evaluated)
    errors = {
        name: {"levels": [], "height": [], "roof": []} for name in ("model", "defaults", "constant_10m", "median")
    }
    for fold in np.array_split(order, folds):
        held = set(int(i) for i in fold)
        guessed = copy.deepcopy(map_data)
        for i in held:
            _hide(guessed.buildings[i])
        guessed = guess_missing(guessed)
        silent = copy.deepcopy(map_data)  # nothing tagged anywhere: the regional defaults alone
        for b in silent.buildings:
            _hide(b)
        silent = guess_missing(silent)
        train_levels = [v for i, v in levels.items() if i not in held]
        train_heights = [v for i, v in heights.items() if i not in held]
        train_roofs = [v for i, v in roofs.items() if i not in held]
        median_levels = float(np.median(train_levels)) if train_levels else OLD_HEIGHT / OLD_STOREY
        median_height = float(np.median(train_heights)) if train_heights else OLD_HEIGHT
        common_roof = max(set(train_roofs), key=train_roofs.count) if train_roofs else "flat"
        for i in sorted(held):
            for name, source in (("model", guessed), ("defaults", silent)):
                b = source.buildings[i]
                _score(errors[name], i, levels, heights, roofs, b.levels, b.height, b.roof_shape)
            _score(errors["constant_10m"], i, levels, heights, roofs, OLD_HEIGHT / OLD_STOREY, OLD_HEIGHT, "flat")
            _score(errors["median"], i, levels, heights, roofs, median_levels, median_height, common_roof)
    return {
        name: {
            "levels_mae": float(np.mean(e["levels"])) if e["levels"] else float("nan"),
            "height_mae_m": float(np.mean(e["height"])) if e["height"] else float("nan"),
            "roof_shape_accuracy": float(np.mean(e["roof"])) if e["roof"] else float("nan"),
        }
        for name, e in errors.items()
    } | {"counts": {"levels": len(levels), "height": len(heights), "roof_shape": len(roofs), "folds": folds}}


def _score(into, i, levels, heights, roofs, guess_levels, guess_height, guess_roof):
    if i in levels:
        into["levels"].append(abs(guess_levels - levels[i]))
    if i in heights:
        into["height"].append(abs(guess_height - heights[i]))
    if i in roofs:
        into["roof"].append(guess_roof == roofs[i])


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
        for b, outline in zip(source, shapely.transform(outlines, lambda c, shift=shift: c + shift)):
            buildings.append(
                dataclasses.replace(
                    b, index=len(buildings), outline=outline, parent=None, tagged=set(b.tagged), guessed=set(b.guessed)
                )
            )
    return dataclasses.replace(map_data, buildings=buildings[:count], trees=[], report=ReadReport())


def run(quick: bool, out_dir: Path) -> BenchResult:
    if not HELSINKI.exists():
        raise UsageError(f"{HELSINKI}: missing; run `make data` to fetch the Helsinki extract")
    helsinki = load_map(HELSINKI)
    scores = evaluate(helsinki)
    many = tiled(helsinki, 20_000 if quick else 100_000)
    start, cpu = time.perf_counter(), time.process_time()
    many = guess_missing(many)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    counts = scores.pop("counts")
    result = BenchResult("guesses", "cpu")
    rows = [
        [name, round(s["levels_mae"], 3), round(s["height_mae_m"], 3), round(s["roof_shape_accuracy"], 3)]
        for name, s in scores.items()
    ]
    result.add_table(
        f"Helsinki extract, {counts['folds']}-fold (seed {SEED}): {counts['levels']} tagged levels, "
        f"{counts['height']} tagged heights, {counts['roof_shape']} tagged roof shapes",
        ["guesser", "levels MAE (storeys)", "height MAE (m)", "roof shape accuracy"],
        rows,
    )
    model, old, median = scores["model"], scores["constant_10m"], scores["median"]
    result.ratios = {
        "levels_mae": model["levels_mae"],
        "height_mae_m": model["height_mae_m"],
        "roof_shape_accuracy": model["roof_shape_accuracy"],
        "constant_10m_levels_mae": old["levels_mae"],
        "constant_10m_height_mae_m": old["height_mae_m"],
        "always_flat_roof_shape_accuracy": old["roof_shape_accuracy"],
        "median_levels_mae": median["levels_mae"],
        "median_height_mae_m": median["height_mae_m"],
        "defaults_levels_mae": scores["defaults"]["levels_mae"],
        "defaults_height_mae_m": scores["defaults"]["height_mae_m"],
        "defaults_roof_shape_accuracy": scores["defaults"]["roof_shape_accuracy"],
    }
    speed = f"guess_{len(many.buildings) // 1000}k"
    result.ratios[f"{speed}_seconds"] = seconds
    result.ratios[f"{speed}_cpu_seconds"] = cpu
    result.targets = {
        "levels_mae": "<= 1.0",
        "height_mae_m": "<= 3.0",
        "roof_shape_accuracy": "> always flat",
        f"{speed}_seconds": "seconds",
    }
    result.notes.append(
        f"{speed}_seconds (wall) and _cpu_seconds (this process): guess_missing on the Helsinki "
        f"buildings tiled to {len(many.buildings):,} (100,000 without --quick, 20,000 with)."
    )
    result.notes.append("Map data © OpenStreetMap contributors, ODbL 1.0.")
    return result
