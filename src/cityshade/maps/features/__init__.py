"""The map features cityshade reads, one module each (see _feature.Feature), in the order their
layers are drawn and `cityshade info` lists them. Adding one: a module with its Feature, listed here."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...scene import Layer
from .._ground import cut_surfaces
from .._model import MapData
from ._feature import Built, Feature, Surface
from .buildings import Buildings, is_building
from .city_objects import CityObjects
from .entrances import Entrances
from .lamps import Lamps
from .land import Land
from .platforms import Platforms
from .rail import Rail
from .streets import Streets
from .trees import Trees
from .water import Water

FEATURES: tuple[Feature, ...] = (
    Buildings(),
    Streets(),
    Rail(),
    Platforms(),
    Land(),
    CityObjects(),
    Water(),
    Trees(),
    Lamps(),
    Entrances(),
)
AREA_TAGS = {key: kind for feature in FEATURES for key, kind in feature.area_tags.items()}


def area_kind(tags: dict[str, str]) -> str | None:
    """The area kind of a polygon that is no building (the first of its tags some feature reads)."""
    if tags.get("highway") and tags.get("area") != "yes":
        return None
    for key, value in tags.items():
        kind = AREA_TAGS.get((key, value))
        if kind is not None:
            return kind
    return None


def point_kind(tags: dict[str, str]) -> str | None:
    """What a tagged node is to the map (named in reports); None: no feature wants it."""
    return next((kind for feature in FEATURES if (kind := feature.point_kind(tags)) is not None), None)


def wanted_line(tags: dict[str, str]) -> bool:
    return any(feature.wants_line(tags) for feature in FEATURES)


def city_layers(data: MapData) -> tuple[Layer, ...]:
    """Every feature's layer, its flat surfaces cut in rank order before its own ground."""
    built = [feature.build(data) for feature in FEATURES]
    claims = [(i, surface) for i, b in enumerate(built) for surface in b.surfaces]
    cut = cut_surfaces([surface for _, surface in claims])
    layers = []
    for i, b in enumerate(built):
        own = [triangles for (owner, _), triangles in zip(claims, cut) if owner == i]
        layers.append(replace(b.layer, ground=np.concatenate([*own, b.layer.ground])))
    return tuple(layers)


__all__ = [
    "FEATURES",
    "Built",
    "Feature",
    "Surface",
    "area_kind",
    "city_layers",
    "is_building",
    "point_kind",
    "wanted_line",
]
