"""Doors and shop fronts from map data: `entrance=*` nodes on an outline put a door exactly there,
buildings without one get a guessed door on the street side (never on a party wall), shops mapped
inside a building give it shop fronts; `cityshade info` counts them; the GPU draws the doors where
the twin's door test says."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cityshade import assets
from cityshade.interior import cast_masses
from cityshade.maps import building_masses, facade_style, guess_missing, load_map, map_city, to_scene
from cityshade.maps.testing import STYLE_BY_USE
from cityshade.render import Renderer, RenderSettings
from cityshade.scene import Camera, door_hit, rotation_y

ENTRANCES = Path(__file__).parents[1] / "data" / "maps" / "entrances.osm"
DOOR_LABEL = assets.LABELS.index("door")


def _map(path: Path = ENTRANCES):
    data = load_map(path)
    data = guess_missing(data)
    return data, {b.source_id: b for b in data.buildings}


def _world(mass, door) -> np.ndarray:
    """A mass's door point in scene (x, z)."""
    p = rotation_y(mass.yaw) @ np.array([door[0], 0.0, door[1]])
    return np.array([p[0] + mass.position[0], p[2] + mass.position[1]])


def _wall_middles(outline) -> np.ndarray:
    """The middles of an outline's walls (map metres), sorted west to east."""
    ring = np.asarray(outline.exterior.coords)
    middles = (ring[:-1] + ring[1:]) / 2
    return middles[np.argsort(middles[:, 0])]


def test_mapped_entrances_become_doors_exactly_there_main_first():
    data, by_id = _map()
    flats = by_id["way/100"]
    main, staircase, stray = data.entrances
    assert (main.kind, staircase.kind) == ("main", "staircase")
    assert flats.doors == [main.position, staircase.position] and "doors" in flats.tagged
    masses = {m.seed: m for m in building_masses(data)}
    doors = masses[flats.index].doors
    assert len(doors) == 2
    for door, entrance in zip(doors, (main, staircase)):
        assert _world(masses[flats.index], door) == pytest.approx(to_scene(entrance.position), abs=0.02)
    normal = rotation_y(masses[flats.index].yaw) @ np.array([doors[0][2], 0.0, doors[0][3]])
    assert normal[[0, 2]] == pytest.approx([0.0, 1.0], abs=0.05), "south (+z; UTM grid north is 2° off)"
    assert data.report.skipped[("entrance", "not on a building's wall (within 0.5 m)")] == 1
    assert stray.kind == "yes"


def test_without_an_entrance_the_door_faces_the_street_and_never_a_party_wall():
    data, by_id = _map()
    office = by_id["way/101"]
    assert "doors" in office.guessed and len(office.doors) == 1
    assert office.doors[0] == pytest.approx(_wall_middles(office.outline)[-1]), (
        "the middle of the wall facing the street"
    )
    mass = next(m for m in building_masses(data) if m.seed == office.index)
    normal = rotation_y(mass.yaw) @ np.array([mass.doors[0][2], 0.0, mass.doors[0][3]])
    assert normal[[0, 2]] == pytest.approx([1.0, 0.0], abs=0.05), "facing east, toward the street"


def test_a_street_behind_the_neighbour_does_not_put_the_door_on_the_party_wall(tmp_path):
    text = ENTRANCES.read_text().replace('lon="24.940900"', 'lon="24.939800"')  # the street west of the flats
    path = tmp_path / "west.osm"
    path.write_text(text)
    _, by_id = _map(path)
    office = by_id["way/101"]
    west, south_or_north, north_or_south, east = _wall_middles(office.outline)
    assert office.doors[0] in (pytest.approx(south_or_north), pytest.approx(north_or_south)), (
        "on the south or north wall, not against the flats"
    )


def test_a_mapped_shop_gives_shop_fronts_and_info_counts_doors(capsys):
    from cityshade.commands import main

    _, by_id = _map()
    assert by_id["way/100"].shop_front and not by_id["way/101"].shop_front
    assert facade_style(by_id["way/100"]) == STYLE_BY_USE["shop"]
    assert main(["info", "--json", str(ENTRANCES)]) == 0
    doors = json.loads(capsys.readouterr().out)["doors"]
    assert doors == {"entrances": 3, "from_entrances": 2, "guessed": 1, "buildings_with_shop_fronts": 1}


def test_map_doors_on_gpu_match_the_twin(gl_context, output_dir):
    city = map_city(_map()[0])
    flats = next(m for m in city.masses if len(m.doors) == 2)
    door = _world(flats, flats.doors[0])
    camera = Camera((door[0] + 2.0, 1.6, door[1] + 9.0), (door[0], 1.2, door[1]), fov_y=60.0)
    size = (160, 120)
    renderer = Renderer(size, RenderSettings(samples=0, god_rays=False, time_of_day=10.0), ctx=gl_context)
    try:
        renderer.set_city(city)
        ids = renderer.render_ids(camera)
        Image.fromarray(renderer.render(camera)).save(output_dir / "map_door.png")
    finally:
        renderer.release()
    dirs = camera.pixel_rays(size).reshape(-1, 3)
    hits = cast_masses(city.masses, camera.eye, dirs)
    twin = np.zeros(len(dirs), dtype=bool)
    for b, mass in enumerate(city.masses):
        sel = np.nonzero((hits.building == b) & ~hits.roof)[0]
        twin[sel[door_hit(hits.local[sel], hits.normal[sel], mass.doors)[0]]] = True
    twin = twin.reshape(size[1], size[0])
    gpu = ids[..., 3] == DOOR_LABEL
    differ = gpu != twin
    print(f"map door: GPU {gpu.sum()} pixels, twin {twin.sum()}, {differ.sum()} differ")
    assert twin.sum() > 300 and differ.sum() <= 0.03 * twin.sum()


def test_geojson_entrance_points_become_doors(tmp_path):
    path = tmp_path / "doors.geojson"
    square = [[24.94, 60.17], [24.9402, 60.17], [24.9402, 60.1701], [24.94, 60.1701], [24.94, 60.17]]
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    {
                        "type": "Feature",
                        "properties": {"building": "yes"},
                        "geometry": {"type": "Polygon", "coordinates": [square]},
                    },
                    {
                        "type": "Feature",
                        "properties": {"entrance": "main"},
                        "geometry": {"type": "Point", "coordinates": [24.9401, 60.17]},
                    },
                ],
            }
        )
    )
    data, _ = _map(path)
    (building,) = data.buildings
    assert building.doors == [data.entrances[0].position] and "doors" in building.tagged
