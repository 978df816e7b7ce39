"""The framed viewpoints of a map: the aerial view frames the buildings (within the file's declared
extent), never the largest polygon; the street view stands on a street people walk, among buildings."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely

from cityshade.api import render_city
from cityshade.maps import (
    STREET_VIEWS,
    Area,
    MapBuilding,
    MapData,
    Road,
    framed_area,
    load_map,
    map_city,
    street_choice,
)

pytestmark = pytest.mark.gl
HELSINKI = (24.9384, 60.1699)


def town(**extra) -> MapData:
    """Nine 20 m houses on a 40 m grid with a residential street through them, and `extra` roads or areas."""
    buildings = [
        MapBuilding(i, f"way/{i}", shapely.box(40 * (i % 3), 40 * (i // 3), 40 * (i % 3) + 20, 40 * (i // 3) + 20))
        for i in range(9)
    ]
    roads = [Road("way/100", shapely.LineString([(-30, 30), (130, 30)]), "residential", 6.0)]
    return MapData(
        Path("town.osm"),
        HELSINKI,
        "EPSG:32635",
        buildings=buildings,
        roads=roads + extra.get("roads", []),
        areas=extra.get("areas", []),
    )


def test_aerial_frames_the_buildings_not_the_farmland_around_them():
    farmland = Area("way/900", shapely.box(-1500, -1500, 1500, 1500), "farmland")
    data = town(areas=[farmland])
    assert framed_area(data).bounds == pytest.approx((-12, -12, 112, 112), abs=0.5)
    instances, _ = render_city(
        map_city(data), camera="aerial", size=(96, 54), frames=0, time="12:00", samples=0, aov="instance"
    )
    share = (instances > 0).mean()
    assert share > 0.2, f"buildings cover {share:.1%} of the aerial frame"


def test_aerial_stays_inside_the_declared_extent():
    data = town()
    data.buildings.append(MapBuilding(9, "way/9", shapely.box(400, 0, 420, 20)))  # cut by the extract's edge
    data.declared_bounds = (-20.0, -20.0, 120.0, 120.0)
    assert framed_area(data).bounds[2] == pytest.approx(120.0)


def test_street_camera_never_stands_on_a_motorway():
    motorway = Road("way/200", shapely.LineString([(-200, 70), (300, 70)]), "motorway", 14.0, lanes=4)
    data = town(roads=[motorway])
    road, a, b = street_choice(data, [b.outline for b in data.buildings])
    assert road.kind == "residential" and road.kind in STREET_VIEWS[0]
    camera = map_city(data).viewpoints["street"]
    x, y = camera.eye[0], -camera.eye[2]
    assert data.roads[0].line.buffer(3.0).contains(shapely.Point(x, y))
    assert abs(camera.forward[0]) > 0.9  # looking along it


def test_street_camera_takes_a_town_road_only_where_no_street_is_walked():
    data = town()
    data.roads = [
        Road("way/200", shapely.LineString([(-200, 70), (300, 70)]), "trunk", 14.0),
        Road("way/201", shapely.LineString([(-30, 30), (130, 30)]), "primary", 12.0),
    ]
    road, _, _ = street_choice(data, [b.outline for b in data.buildings])
    assert road.kind == "primary"
    data.roads = data.roads[:1]
    assert street_choice(data, [b.outline for b in data.buildings]) is None


@pytest.mark.parametrize("fixture, least", [("helsinki_pbf", 0.22), ("silent_pbf", 0.06)])
def test_real_maps_street_class_and_aerial_building_share(request, fixture, least):
    """Before: the aerial views framed every polygon (buildings covered 14% of Helsinki's frame and
    3.7% of the silent town's) and the street view chose roads by width."""
    data = load_map(request.getfixturevalue(fixture))
    city = map_city(data)
    from cityshade.maps import guess_missing

    guessed = guess_missing(data)
    road, _, _ = street_choice(guessed, [b.outline for b in guessed.buildings if b.drawn])
    assert road.kind in STREET_VIEWS[0], road.kind
    instances, _ = render_city(city, camera="aerial", size=(96, 54), frames=0, time="12:00", samples=0, aov="instance")
    share = float((instances > 0).mean())
    assert share > least, f"buildings cover {share:.1%} of the aerial frame"


def test_the_files_bounds_are_read(tmp_path):
    path = tmp_path / "bounded.osm"
    path.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<osm version="0.6">\n'
        ' <bounds minlat="60.1690" minlon="24.9370" maxlat="60.1710" maxlon="24.9410"/>\n'
        ' <node id="1" lat="60.1700" lon="24.9390"/><node id="2" lat="60.1700" lon="24.9392"/>\n'
        ' <node id="3" lat="60.1701" lon="24.9392"/><node id="4" lat="60.1701" lon="24.9390"/>\n'
        ' <way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>'
        '<tag k="building" v="yes"/></way>\n</osm>\n'
    )
    x0, y0, x1, y1 = load_map(path).declared_bounds
    # 0.004 degrees each way at 60.17 N; the UTM grid turns 1.8 degrees there, so the box grows a little
    assert x1 - x0 == pytest.approx(222, rel=0.05) and y1 - y0 == pytest.approx(222.6, rel=0.05)
