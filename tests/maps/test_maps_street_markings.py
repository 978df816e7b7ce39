"""Street markings and pavements by road class and width: no centre line on residential streets or
under CENTRE_LINE_WIDTH unless `lanes` is tagged, lanes on motorways, no pavements beside motorways
and trunk roads unless `sidewalk=*` says so."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely

from cityshade.maps import MapData, Road
from cityshade.maps.features.streets import CENTRE_LINE_WIDTH, lane_lines, street_surfaces

LINE = shapely.LineString([(0, 0), (200, 0)])


def painted(road: Road) -> int:
    solid, dashed = lane_lines([road])
    return len(solid) + len(dashed)


@pytest.mark.parametrize(
    "road, lines",
    [
        (Road("way/1", LINE, "residential", 8.0), 0),  # a residential street: not painted
        (Road("way/2", LINE, "residential", 8.0, lanes=2), 1),  # unless its lanes are tagged
        (Road("way/3", LINE, "tertiary", CENTRE_LINE_WIDTH - 0.5), 0),  # too narrow for two painted lanes
        (Road("way/4", LINE, "tertiary", 7.0), 1),
        (Road("way/5", LINE, "motorway", 7.5, oneway=True), 1),  # two lanes each way: one divider
        (Road("way/6", LINE, "trunk", 14.0), 3),  # two each way: a centre line and two dividers
    ],
)
def test_centre_lines_and_lanes_by_class_and_width(road, lines):
    assert painted(road) == lines


def _pavement(road: Road) -> float:
    data = MapData(Path("roads.osm"), (24.94, 60.17), "EPSG:32635", roads=[road])
    return street_surfaces(data).pavement.area


def test_no_pavement_beside_a_motorway_unless_tagged():
    assert _pavement(Road("way/1", LINE, "motorway", 14.0, oneway=True)) == 0.0
    assert _pavement(Road("way/2", LINE, "trunk", 14.0)) == 0.0
    assert _pavement(Road("way/3", LINE, "trunk", 14.0, sidewalk="right")) > 200.0
    assert _pavement(Road("way/4", LINE, "primary", 10.0)) > 200.0


def test_info_lists_water_apart_from_its_green_breakdown(tmp_path, capsys):
    from cityshade.commands import main

    square = '<way id="{w}">{nds}<tag k="{k}" v="{v}"/></way>'
    nodes, ways = [], []
    for w, (k, v, x) in enumerate([("natural", "water", 0.0), ("leisure", "park", 0.002), ("building", "yes", 0.004)]):
        ids = [10 * w + i for i in range(1, 5)]
        for i, (dx, dy) in zip(ids, [(0, 0), (0.001, 0), (0.001, 0.001), (0, 0.001)]):
            nodes.append(f'<node id="{i}" lat="{60.17 + dy:.6f}" lon="{24.94 + x + dx:.6f}"/>')
        nds = "".join(f'<nd ref="{i}"/>' for i in [*ids, ids[0]])
        ways.append(square.format(w=100 + w, nds=nds, k=k, v=v))
    path = tmp_path / "areas.osm"
    path.write_text('<?xml version="1.0"?>\n<osm version="0.6">\n' + "\n".join(nodes + ways) + "\n</osm>\n")
    assert main(["info", str(path)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("water:"))
    green = line.split("green:")[1]
    assert "park" in green and "water" not in green, line
