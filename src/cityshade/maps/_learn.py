"""Estimates of levels, storey height and roof shape from urban form, with a confidence for each.

Levels: gradient-boosted trees (LightGBM) predict log(levels / the type's regional default) from the
features of `_form.py`. A prior trained on the tagged buildings of several cities ships with the package
(`guess_prior.json.gz`, rebuilt by scripts/build-guess-prior.py); where the map itself tags the levels
of at least LOCAL_MIN buildings, a few more trees are grown on them on top of the prior (the prior's
prediction is their starting score), so the map's own habits correct the prior. The confidence of a
guessed level count is the chance that it lies within one storey of the truth: a second model, trained
on the prior's errors in cities it had not seen, predicts the typical error, read as a Laplace spread.

Roof: the prior's probability that the roof is flat, moved by the map's tagged roofs around (a vote,
closer counts more) and decided at one half; a pitched roof takes the shape the map's roofs nearby and
of its type vote for (gabled by default). Its confidence is the probability of the side chosen.

Height: where tagged buildings share a wall with it (the block), their height; else levels x storey.
Storey height: the mean of tagged height / levels per type, shrunk toward the regional default.
Deterministic: LightGBM runs on one thread with fixed seeds, so the same map gives the same guesses.
"""

from __future__ import annotations

import gzip
import json
import math
from collections import Counter
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import lightgbm
import numpy as np

from ._defaults import GENERIC
from ._form import CATEGORICAL, FEATURES, Form, tagged_value
from ._model import ROOF_SHAPES, MapBuilding, MapData

PRIOR_FILE = Path(__file__).with_name("guess_prior.json.gz")
LOCAL_MIN = 10  # tagged level counts a map needs before trees are grown on its own buildings
LOCAL_TREES = 80
SHRINK = 8.0  # tagged buildings at which the map's own typical departure counts half
# The share of the prior's correction applied. Measured leave-one-city-out on its three cities, half of it
# guesses better than all of it or none, on silent maps and as the start of the map's own trees alike.
PRIOR_WEIGHT = 0.5
ROOF_PRIOR_WEIGHT = 0.5  # the same for the prior's log odds of a flat roof
LOCAL_PARAMS = {
    "objective": "l1",
    "learning_rate": 0.08,
    "num_leaves": 7,
    "min_data_in_leaf": 5,
    "lambda_l2": 5.0,
    "deterministic": True,
    "num_threads": 1,
    "seed": 7,
    "verbosity": -1,
}
LANDMARK_ROOFS = {"dome", "onion", "round", "cone", "pyramidal"}  # not spread to the buildings around
PRIOR_VOTES = 3.0  # the regional default roof counts as this many tagged neighbours
ROOF_VOTE = 4.0  # weight of one tagged roof nearby (times its distance weight)
STOREY_PRIOR = 4.0  # the regional storey height counts as this many tagged buildings
ONE_STOREY = 1.0  # a guessed level count this close to the truth counts as right (the confidence's event)


@dataclass(frozen=True)
class Prior:
    """The shipped models: levels (log ratio to the type default), its typical error, P(flat roof)."""

    name: str  # "all cities", or "without <city>" for the leave-one-city-out measurements
    levels: lightgbm.Booster
    levels_error: lightgbm.Booster
    flat: lightgbm.Booster
    cities: dict  # city name -> {"bbox": [west, south, east, north], "levels": tagged count, ...}


@cache
def _prior_document() -> dict:
    with gzip.open(PRIOR_FILE, "rt", encoding="utf-8") as text:
        document = json.load(text)
    if tuple(document["features"]) != FEATURES:
        raise RuntimeError(f"{PRIOR_FILE}: built for other features; rebuild it with scripts/build-guess-prior.py")
    return document


@cache
def load_prior(without: str | None = None) -> Prior:
    """The shipped prior, or (`without` a city it was trained on) the one trained without that city."""
    document = _prior_document()
    key = "all" if without is None else f"without {without}"
    if key not in document["models"]:
        raise KeyError(f"{PRIOR_FILE}: no prior {key!r}; it has {', '.join(sorted(document['models']))}")
    models = document["models"][key]
    return Prior(
        "all cities" if without is None else key,
        levels=lightgbm.Booster(model_str=models["levels"]),
        levels_error=lightgbm.Booster(model_str=document["levels_error"]),
        flat=lightgbm.Booster(model_str=models["flat"]),
        cities=document["cities"],
    )


def city_bounds(map_data: MapData) -> list[float]:
    """[west, south, east, north] degrees of the map's extent (from its origin and metre bounds)."""
    lon, lat = map_data.origin
    x0, y0, x1, y1 = map_data.bounds()
    per_lon = 111_320.0 * max(math.cos(math.radians(lat)), 1e-6)
    return [round(v, 5) for v in (lon + x0 / per_lon, lat + y0 / 111_320.0, lon + x1 / per_lon, lat + y1 / 111_320.0)]


def prior_city(map_data: MapData) -> str | None:
    """The prior's training city whose bounds overlap the map's, if any."""
    west, south, east, north = city_bounds(map_data)
    for name, city in _prior_document()["cities"].items():
        w, s, e, n = city["bbox"]
        if west <= e and w <= east and south <= n and s <= north:
            return name
    return None


@dataclass
class Estimates:
    levels: np.ndarray  # storeys below the roof
    levels_confidence: np.ndarray  # chance the guess is within one storey
    levels_spread: np.ndarray  # typical error of the guess, in storeys
    storey: np.ndarray  # metres floor to floor
    roof_shape: np.ndarray  # object array of ROOF_SHAPES values
    roof_confidence: np.ndarray  # probability of the side (flat or pitched) chosen
    block_height: np.ndarray  # tagged height of the buildings sharing a wall (distance-weighted), NaN if none
    local_model: bool  # whether trees were grown on the map's own tagged buildings


def _predict(booster: lightgbm.Booster, x: np.ndarray, raw: bool = False) -> np.ndarray:
    return booster.predict(x, raw_score=raw, num_threads=1)


def _local_levels(x: np.ndarray, target: np.ndarray, known: np.ndarray, start: np.ndarray) -> np.ndarray | None:
    """Trees grown on the map's tagged buildings over the prior's prediction `start`; their correction."""
    count = int(known.sum())
    if count < LOCAL_MIN:
        return None
    # The map's typical departure from the start first (trees on near-identical buildings find no split),
    # shrunk toward none when few buildings are tagged.
    bias = float(np.median(target[known] - start[known])) * count / (count + SHRINK)
    data = lightgbm.Dataset(
        x[known],
        target[known],
        init_score=start[known] + bias,
        feature_name=list(FEATURES),
        categorical_feature=list(CATEGORICAL),
        free_raw_data=False,
        params={"verbosity": -1, "min_data_in_bin": 3},
    )
    booster = lightgbm.train(LOCAL_PARAMS, data, num_boost_round=LOCAL_TREES)
    return bias + _predict(booster, x)


def regional_defaults(buildings: list[MapBuilding], form: Form) -> Estimates:
    """The regional defaults of each building's type, size and form alone: nothing learnt (a baseline)."""
    defaults = form.defaults
    n = len(buildings)
    return Estimates(
        form.default_levels.copy(),
        np.full(n, np.nan),
        np.full(n, np.nan),
        np.array([d.storey for d in defaults], float),
        np.array([d.roof_shape for d in defaults], dtype=object),
        np.full(n, np.nan),
        np.full(n, np.nan),
        False,
    )


def estimate(buildings: list[MapBuilding], form: Form, prior: Prior) -> Estimates:
    """Estimates for every building (tagged ones too: the caller keeps tagged values)."""
    defaults = form.defaults
    x = form.values
    default_levels = np.array([d.levels for d in defaults], float)
    log_default = np.log(default_levels)
    tagged = tagged_value(buildings, "levels")
    known = np.isfinite(tagged)
    target = np.log(np.maximum(np.where(known, tagged, 1.0), 1.0)) - log_default
    start = PRIOR_WEIGHT * _predict(prior.levels, x)
    local = _local_levels(x, target, known, start)
    ratio = start if local is None else start + local
    levels = np.clip(np.round(default_levels * np.exp(ratio)), 1.0, 80.0)
    small = np.array([d.small for d in defaults])
    levels[small] = 1.0
    # The typical error in log levels, read as a Laplace spread: P(|error| <= one storey).
    spread_log = np.maximum(_predict(prior.levels_error, x), 0.02)
    spread = np.maximum(spread_log * levels, 0.05)
    confidence = 1.0 - np.exp(-(ONE_STOREY + 0.5) / spread)  # a count is right within one storey: |e| < 1.5
    confidence[small] = np.maximum(confidence[small], 0.9)
    roofs, roof_confidence = _roof_shapes(buildings, defaults, form, prior)
    heights = tagged_value(buildings, "height")
    block_height, _ = form.around.block_mean(heights, np.isfinite(heights))
    return Estimates(
        levels,
        confidence,
        spread,
        _storeys(buildings, np.array([d.storey for d in defaults], float)),
        roofs,
        roof_confidence,
        block_height,
        local is not None,
    )


def _storeys(buildings, default_storey) -> np.ndarray:
    """Per type: (prior * default + sum of tagged storey heights) / (prior + count)."""
    sums, counts = Counter(), Counter()
    for b in buildings:
        if {"height", "levels"} <= b.tagged and b.levels > (b.min_level or 0):
            walls = b.height - (b.roof_height or 0.0) - (b.min_height or 0.0)
            storey = walls / (b.levels - (b.min_level or 0.0))
            if 2.2 <= storey <= 8.0:
                sums[b.kind] += storey
                counts[b.kind] += 1
    kinds = [b.kind for b in buildings]
    learned = [(STOREY_PRIOR * d + sums[k]) / (STOREY_PRIOR + counts[k]) for k, d in zip(kinds, default_storey)]
    return np.array(learned, float)


def _roof_votes(buildings, defaults, form: Form) -> np.ndarray:
    """Votes per building and roof shape: the regional default, the map's own mix for the type, the
    tagged roofs around (domes and their kin only within their own building or named type)."""
    n = len(buildings)
    shapes = np.array(
        [b.roof_shape if "roof_shape" in b.tagged and b.roof_shape in ROOF_SHAPES else "" for b in buildings],
        dtype=object,
    )
    known = shapes != ""
    code = {s: k for k, s in enumerate(ROOF_SHAPES)}
    votes = np.zeros((n, len(ROOF_SHAPES)))
    votes[np.arange(n), [code[d.roof_shape] for d in defaults]] = PRIOR_VOTES
    kinds = np.array([b.kind for b in buildings], dtype=object)
    names, kind_index = np.unique(kinds, return_inverse=True)
    mix = np.zeros((len(names), len(ROOF_SHAPES)))
    np.add.at(mix, (kind_index[known], [code[s] for s in shapes[known]]), 1.0)
    votes += PRIOR_VOTES * mix[kind_index] / np.maximum(mix.sum(axis=1, keepdims=True), 1.0)[kind_index]
    around = form.around
    for shape in sorted(set(shapes[known])):
        if shape not in LANDMARK_ROOFS:
            votes[:, code[shape]] += ROOF_VOTE * around.sum_around((shapes == shape).astype(float))
            continue
        # A dome belongs to its building: the parts it shares a wall with, and nearby buildings of the
        # same named type (the chapels of one monastery), take it; ordinary buildings around do not.
        votes[:, code[shape]] += ROOF_VOTE * around.block_mean(np.ones(n), shapes == shape)[1]
        for kind in sorted(set(kinds[shapes == shape]) - GENERIC):
            same = kinds == kind
            votes[same, code[shape]] += ROOF_VOTE * around.sum_around(((shapes == shape) & same).astype(float))[same]
    return votes


def _roof_shapes(buildings, defaults, form: Form, prior: Prior):
    """The roof shape of every building and the probability of its side (flat or pitched)."""
    votes = _roof_votes(buildings, defaults, form)
    flat = ROOF_SHAPES.index("flat")
    # The votes (the regional default, the map's own roofs by type and around) give the odds of a flat
    # roof; the prior moves them by PRIOR_WEIGHT of its own log odds.
    flat_votes = votes[:, flat]
    pitched_votes = votes.sum(axis=1) - flat_votes
    logit = ROOF_PRIOR_WEIGHT * _predict(prior.flat, form.values, raw=True)
    logit = logit + np.log((flat_votes + 1.0) / (pitched_votes + 1.0))
    p_flat = 1.0 / (1.0 + np.exp(-logit))
    pitched_votes_only = votes.copy()
    pitched_votes_only[:, flat] = -math.inf
    pitched = np.array(ROOF_SHAPES, dtype=object)[pitched_votes_only.argmax(axis=1)]
    is_flat = p_flat >= 0.5
    shapes = np.where(is_flat, "flat", pitched).astype(object)
    return shapes, np.where(is_flat, p_flat, 1.0 - p_flat)
