"""Dormers only where the map says so or by the documented rule (maps/_roofs.py), not on every
pitched roof a guessed attic sits under; counted from the meshes of hand-made and real buildings."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely

from cityshade.maps import MapBuilding, MapData, load_map, map_city
from cityshade.maps.testing import DORMER_EAVES, DORMER_SHARE, has_dormers

ROOFS = Path(__file__).parents[1] / "data" / "maps" / "roofs_dormers.osm"
LONG = shapely.box(0, 0, DORMER_EAVES + 4, 8)
SHORT = shapely.box(0, 0, DORMER_EAVES - 2, 8)


def house(index: int, kind: str = "house", guessed: bool = True, **tags) -> MapBuilding:
    return MapBuilding(
        index, f"way/{index}", LONG, kind=kind, roof_shape="gabled", roof_levels=1.0,
        guessed=frozenset({"roof_levels"} if guessed else ()), tags=tags,
    )  # fmt: skip


def test_tagged_roof_levels_or_dormer_tags_decide():
    assert has_dormers(house(1, guessed=False), LONG)
    assert not has_dormers(house(1, guessed=False, **{"roof:dormers": "no"}), LONG)
    assert has_dormers(house(1, kind="industrial", **{"roof:dormers": "3"}), LONG)


def test_guessed_attics_get_dormers_on_one_house_in_so_many():
    share = sum(has_dormers(house(i), LONG) for i in range(2000)) / 2000
    assert share == pytest.approx(DORMER_SHARE, abs=0.04)  # before: every one
    assert not any(has_dormers(house(i), SHORT) for i in range(200)), "short eaves: none"
    assert not any(has_dormers(house(i, kind="industrial"), LONG) for i in range(200)), "not on a shed"


def test_a_row_of_guessed_houses_is_not_all_dormers():
    buildings = [
        MapBuilding(i, f"way/{i}", shapely.box(30 * i, 0, 30 * i + 14, 9), kind="house", levels=2.0) for i in range(12)
    ]
    city = map_city(MapData(Path("row.osm"), (24.94, 60.17), "EPSG:32635", buildings=buildings))
    with_rooms = [m for m in city.masses if m.roof.attic_storey > 0]
    assert with_rooms, "the guess gives these houses attics"
    assert 0 < sum(m.roof.dormers for m in with_rooms) < len(with_rooms)


def test_the_tagged_dormer_file_keeps_its_dormers():
    city = map_city(load_map(ROOFS))
    assert any(m.roof.dormers and m.roof.attic_storey > 0 for m in city.masses)
