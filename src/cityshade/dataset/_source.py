"""What a dataset is drawn from: a City with its streets, and each building's source id.

A building of a map may be several masses (building parts, multipolygon pieces): instance images
number the buildings (1, 2, ... in the map's order) and, in a second channel, each mass within its
building (1, 2, ...). A built-in city's masses are one building each, with no source id.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scene import City, make_city
from ._views import Streets


@dataclass
class Source:
    name: str  # the map file's path or the built-in city's name, as given
    city: City
    streets: Streets
    instances: list[str | None]  # per building (building number - 1): the map's id ("way/123"), None if built in
    # per mass: its building number (1-based) and its part number within the building (1-based)
    mass_building: np.ndarray = field(default_factory=lambda: np.zeros(0, np.uint32))
    mass_part: np.ndarray = field(default_factory=lambda: np.zeros(0, np.uint32))

    @property
    def has_date(self) -> bool:
        return self.city.origin is not None


def _masses_per_building(map_data) -> list[tuple[str, int]]:
    """(map id, number of masses) of every drawn building, in the order building_masses lays them out."""
    from ..maps import MapData, building_masses

    counts = []
    for building in map_data.buildings:
        if building.drawn:
            alone = MapData(map_data.source, map_data.origin, map_data.crs, buildings=[building])
            counts.append((building.source_id, len(building_masses(alone))))
    return counts


def building_tables(counts: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Per mass (building number, part number), both 1-based, from each building's mass count."""
    buildings = np.repeat(np.arange(1, len(counts) + 1, dtype=np.uint32), counts)
    starts = np.repeat(np.cumsum([0, *counts[:-1]]).astype(np.int64), counts)
    parts = (np.arange(len(buildings)) - starts + 1).astype(np.uint32)
    return buildings, parts


def load_source(map_path: Path | None = None, city: str | None = None, terrain: Path | None = None) -> Source:
    if map_path is not None:
        from ..maps import city_from_guessed, guess_missing, load_map

        map_data = guess_missing(load_map(map_path, terrain=terrain))  # what the map leaves out
        layout = city_from_guessed(map_data)
        counts = _masses_per_building(map_data)
        buildings, parts = building_tables([n for _, n in counts])
        if len(buildings) != len(layout.masses):
            raise RuntimeError(f"{map_path}: {len(buildings)} source ids for {len(layout.masses)} building masses")
        return Source(str(map_path), layout, Streets.from_map(map_data), [i for i, _ in counts], buildings, parts)
    layout = make_city(city)
    buildings, parts = building_tables([1] * len(layout.masses))
    return Source(city, layout, Streets.from_city(layout), [None] * len(layout.masses), buildings, parts)
