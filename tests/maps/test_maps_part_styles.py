"""The parts of one building (Simple 3D Buildings `building:part`) share one facade style and wall
colour unless their own tags differ (tests/data/maps/parts.osm, hand-made)."""

from __future__ import annotations

from pathlib import Path

import shapely

from cityshade.maps import MapBuilding, MapData, building_masses, guess_missing, load_map

PARTS = Path(__file__).parents[1] / "data" / "maps" / "parts.osm"


def _by_source(data):
    data = guess_missing(data)
    masses = building_masses(data)
    ids = []
    for b in data.buildings:  # the masses in the order building_masses lays them out
        if b.drawn:
            ids += [b.source_id] * len(building_masses(MapData(data.source, data.origin, data.crs, buildings=[b])))
    return dict(zip(ids, masses))


def test_parts_share_their_outlines_style_and_colour():
    masses = _by_source(load_map(PARTS))
    for outline, part in (("way/200", "way/201"), ("way/600", "way/601")):
        assert masses[outline].style == masses[part].style, (outline, part)
        assert masses[outline].wall_colour == masses[part].wall_colour, (outline, part)


def test_a_part_tagged_otherwise_keeps_its_own():
    outline = MapBuilding(0, "way/1", shapely.box(0, 0, 20, 10), levels=3.0)
    part = MapBuilding(
        1, "way/2", shapely.box(0, 0, 10, 10), is_part=True, parent=0, levels=6.0,
        building_colour=(0.2, 0.3, 0.8), building_material="glass", kind="office",
    )  # fmt: skip
    data = MapData(Path("p.osm"), (24.94, 60.17), "EPSG:32635", buildings=[outline, part])
    masses = _by_source(data)
    assert masses["way/2"].wall_colour == (0.2, 0.3, 0.8) != masses["way/1"].wall_colour
