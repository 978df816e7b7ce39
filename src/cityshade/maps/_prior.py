"""How the guessing prior (`guess_prior.json.gz`) is trained from maps with tagged buildings.

Each map gives rows as `bench guesses` measures: its tagged buildings are split into FOLDS groups and,
group by group, their size and roof tags hidden (`hide_sizes`) before the features are computed, so a
row describes a building whose own tags are gone but whose tagged neighbours are known; a second copy
of every row describes it on a map with nothing tagged at all (the silent towns most maps are). The
levels model learns log(levels / regional default), the roof model whether the roof is flat, the error
model the levels model's absolute error (in log levels) on cities it was not trained on. The file holds
the models trained on all cities and, for each city, those trained without it (the honest measure of
that city in `bench guesses`). LightGBM runs on one thread with fixed seeds and the file is written
without a time stamp, so the same maps give the same bytes.
"""

from __future__ import annotations

import copy
import gzip
import io
import json
from dataclasses import dataclass

import lightgbm
import numpy as np

from ._defaults import resolve_contradictions
from ._form import CATEGORICAL, FEATURES, urban_form
from ._learn import city_bounds
from ._model import MapData

FOLDS = 5
SEED = 17
HIDDEN = ("height", "min_height", "levels", "min_level", "roof_shape", "roof_height", "roof_levels")
# Three cities differ more than any two buildings of one: the prior is kept shallow and slow (few, small
# leaves of many buildings each), so that on a city it has not seen it stays near the regional defaults.
LEVELS_PARAMS = {
    "objective": "l1",
    "learning_rate": 0.02,
    "num_leaves": 7,
    "min_data_in_leaf": 60,
    "lambda_l2": 1.0,
    "feature_fraction": 0.9,
    "feature_fraction_seed": SEED,
    "deterministic": True,
    "num_threads": 1,
    "seed": SEED,
    "verbosity": -1,
}
LEVELS_TREES = 80
FLAT_PARAMS = LEVELS_PARAMS | {"objective": "binary", "learning_rate": 0.05, "min_data_in_leaf": 5}
FLAT_TREES = 60
ERROR_PARAMS = LEVELS_PARAMS | {"objective": "l2", "learning_rate": 0.05, "min_data_in_leaf": 20}
ERROR_TREES = 60
# Features that only name the city in three cities (the streets' orientation): left out of the prior.
CITY_ONLY = ("orientation_cos", "orientation_sin")
DATASET_PARAMS = {"verbosity": -1, "min_data_in_bin": 3}


def hide_sizes(building):
    """Forget what the map said of a building's size and roof: it becomes as silent as most of OpenStreetMap."""
    for name in HIDDEN:
        if name in building.tagged:
            setattr(building, name, None)
            building.tagged.discard(name)


@dataclass
class Rows:
    """Training rows of one map: features, log(levels / default) (NaN: untagged), flat roof 0/1 (NaN)."""

    city: str
    x: np.ndarray
    levels: np.ndarray
    flat: np.ndarray


def _settled(map_data: MapData) -> MapData:
    settled = copy.deepcopy(map_data)
    for building in settled.buildings:
        resolve_contradictions(building, settled.report)
    return settled


def training_rows(map_data: MapData, city: str, folds: int = FOLDS, seed: int = SEED) -> Rows:
    """The rows of every tagged building of `map_data`, described with its own tags hidden (see above)."""
    settled = _settled(map_data)
    buildings = settled.buildings
    levels = np.array([b.levels if "levels" in b.tagged else np.nan for b in buildings], float)
    flat = np.array([float(b.roof_shape == "flat") if "roof_shape" in b.tagged else np.nan for b in buildings])
    evaluated = np.flatnonzero(np.isfinite(levels) | np.isfinite(flat))
    order = np.random.default_rng(seed).permutation(evaluated)
    groups = [set(int(i) for i in fold) for fold in np.array_split(order, folds)] + [set(evaluated.tolist())]
    xs, ys, fs = [], [], []
    for held in groups:
        hidden = copy.deepcopy(settled)
        for i in held:
            hide_sizes(hidden.buildings[i])
        form = urban_form(hidden)
        rows = np.array(sorted(held), np.int64)
        xs.append(form.values[rows])
        ys.append(np.log(np.maximum(levels[rows], 1.0)) - np.log(form.default_levels[rows]))
        fs.append(flat[rows])
    return Rows(city, np.concatenate(xs), np.concatenate(ys), np.concatenate(fs))


def _fit(params: dict, rounds: int, x: np.ndarray, y: np.ndarray) -> lightgbm.Booster:
    use = np.isfinite(y)
    if not use.any():
        raise ValueError("no tagged buildings to train on (levels and roof:shape both needed)")
    x = x.copy()
    x[:, [FEATURES.index(name) for name in CITY_ONLY]] = np.nan
    data = lightgbm.Dataset(
        x[use], y[use], feature_name=list(FEATURES), categorical_feature=list(CATEGORICAL), params=DATASET_PARAMS
    )
    return lightgbm.train(params, data, num_boost_round=rounds)


def _models(rows: list[Rows]) -> tuple[lightgbm.Booster, lightgbm.Booster]:
    x = np.concatenate([r.x for r in rows])
    levels = _fit(LEVELS_PARAMS, LEVELS_TREES, x, np.concatenate([r.levels for r in rows]))
    flat = _fit(FLAT_PARAMS, FLAT_TREES, x, np.concatenate([r.flat for r in rows]))
    return levels, flat


def train_prior(maps: dict[str, MapData]) -> dict:
    """The prior document for `maps` (city name -> map): models on all cities and without each one."""
    rows = [training_rows(m, name) for name, m in sorted(maps.items())]
    sets, errors_x, errors_y = {}, [], []
    for held in rows:
        others = [r for r in rows if r is not held]
        levels, flat = _models(others)
        sets[f"without {held.city}"] = (levels, flat)
        predicted = levels.predict(held.x, num_threads=1)
        errors_x.append(held.x)
        errors_y.append(np.abs(held.levels - predicted))  # NaN where untagged: left out by _fit
    error = _fit(ERROR_PARAMS, ERROR_TREES, np.concatenate(errors_x), np.concatenate(errors_y))
    sets["all"] = _models(rows)
    document = {
        "version": 1,
        "features": list(FEATURES),
        "cities": {
            r.city: {
                "bbox": city_bounds(maps[r.city]),
                "rows_levels": int(np.isfinite(r.levels).sum()),
                "rows_roof": int(np.isfinite(r.flat).sum()),
            }
            for r in rows
        },
        "models": {},
    }
    document["levels_error"] = error.model_to_string()
    for key, (levels, flat) in sorted(sets.items()):
        document["models"][key] = {"levels": levels.model_to_string(), "flat": flat.model_to_string()}
    return document


def prior_bytes(document: dict) -> bytes:
    """The document as gzip'd JSON without a time stamp: the same document gives the same bytes."""
    buffer = io.BytesIO()
    with gzip.GzipFile(fileobj=buffer, mode="wb", compresslevel=9, mtime=0) as out:
        out.write(json.dumps(document, sort_keys=True, separators=(",", ":")).encode("utf-8"))
    return buffer.getvalue()
