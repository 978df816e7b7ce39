"""`load_footprints(path)`: the City of a map file (`maps.load_map` then `maps.map_city`).

The name predates the map readers; it stays for scripts that use it. Any format `load_map` reads
works (OpenStreetMap .osm.pbf/.osm, GeoJSON, CityJSON), with the same repairs and errors.
"""

from __future__ import annotations

from pathlib import Path

from ._city import City


def load_footprints(path: Path | str) -> City:
    from ..maps import load_map, map_city  # maps builds on scene, so it is imported on use

    return map_city(load_map(path))
