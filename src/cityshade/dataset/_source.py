"""What a dataset is drawn from: a City with its streets, and each building's source id."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..scene import City, make_city
from ._views import Streets


@dataclass
class Source:
    name: str  # the map file's path or the built-in city's name, as given
    city: City
    streets: Streets
    instances: list[str | None]  # per building mass (instance id - 1): the map's id ("way/123"), None if built in

    @property
    def has_date(self) -> bool:
        return self.city.origin is not None


def _mass_source_ids(map_data) -> list[str]:
    """The map id of every mass, in the order building_masses lays them out (one building at a time)."""
    from ..maps import MapData, building_masses

    ids = []
    for building in map_data.buildings:
        if building.drawn:
            alone = MapData(map_data.source, map_data.origin, map_data.crs, buildings=[building])
            ids += [building.source_id] * len(building_masses(alone))
    return ids


def load_source(map_path: Path | None = None, city: str | None = None) -> Source:
    if map_path is not None:
        from ..maps import city_from_guessed, guess_missing, load_map

        map_data = guess_missing(load_map(map_path))  # what the map leaves out
        layout = city_from_guessed(map_data)
        instances = _mass_source_ids(map_data)
        if len(instances) != len(layout.masses):
            raise RuntimeError(f"{map_path}: {len(instances)} source ids for {len(layout.masses)} building masses")
        return Source(str(map_path), layout, Streets.from_map(map_data), instances)
    layout = make_city(city)
    return Source(city, layout, Streets.from_city(layout), [None] * len(layout.masses))
