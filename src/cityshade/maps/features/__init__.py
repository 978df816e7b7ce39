"""The map features cityshade reads, one module each (see _feature.Feature), in the order their
layers are drawn and `cityshade info` lists them. Adding one: a module with its Feature, listed here."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...scene import Layer
from .._draping import draping
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
from .terrain import Relief
from .trees import Trees
from .water import Water

FEATURES: tuple[Feature, ...] = (
    Relief(),
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
    """Every feature's layer, its flat surfaces cut in rank order before its own ground, all of it laid
    on the map's terrain where it has one (maps/_draping.py)."""
    built = [feature.build(data) for feature in FEATURES]
    claims = [(i, surface) for i, b in enumerate(built) for surface in b.surfaces]
    cut = cut_surfaces([surface for _, surface in claims])
    on_terrain = draping(data)
    layers = []
    for i, b in enumerate(built):
        own = np.concatenate(
            [np.zeros((0, 4), np.float32)] + [triangles for (owner, _), triangles in zip(claims, cut) if owner == i]
        )
        layer = b.layer
        if on_terrain is not None:
            own, layer = on_terrain.ground(own), on_terrain.layer(layer)
        layers.append(replace(layer, ground=np.concatenate([own, layer.ground])))
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
