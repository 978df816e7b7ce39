"""map_city: buildings, framed cameras, and the sun over the map, from small hand-made maps."""

from __future__ import annotations

import sys
import types
from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import MapBuilding, MapData, Road, load_map, map_city, street_segment, sun_and_moon, to_scene
from cityshade.scene import FLAGS, USES, box

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

HELSINKI = (24.9384, 60.1699)


def _prisms(map_data):
    """Flat-roofed prisms from the outlines' bounding boxes: stands in until building_masses lands."""
    masses = []
    for b in map_data.buildings:
        x0, y0, x1, y1 = b.outline.bounds
        ((sx, sz),) = to_scene([(x0, y1)])
        masses.append(box((sx, sz), x1 - x0, y1 - y0, b.height or 10.0))
    return masses


@pytest.fixture(autouse=True)
def building_stage(monkeypatch):
    try:
        import cityshade.maps._masses  # noqa: F401
    except ImportError:
        monkeypatch.setitem(sys.modules, "cityshade.maps._masses", types.SimpleNamespace(building_masses=_prisms))


def square(x, y, size):
    return shapely.box(x, y, x + size, y + size)


def block_map() -> MapData:
    """Nine 30 m buildings on a 60 m grid, streets between them: an east-west avenue 20 m wide and
    narrow north-south residential streets."""
    buildings = [
        MapBuilding(i, f"way/{i}", square(60 * (i % 3), 60 * (i // 3), 30.0), height=12.0 + 6 * i) for i in range(9)
    ]
    roads = [Road("way/100", shapely.LineString([(-20, 45), (170, 45)]), "primary", 20.0, lanes=4)]
    roads += [
        Road(f"way/{101 + k}", shapely.LineString([(45 + 60 * k, -20), (45 + 60 * k, 170)]), "residential", 6.0)
        for k in range(2)
    ]
    return MapData(Path("blocks.osm"), HELSINKI, "EPSG:32635", buildings=buildings, roads=roads)


def test_map_city_has_every_building():
    city = map_city(block_map())
    assert len(city.masses) == 9
    assert city.origin == HELSINKI and city.crs == "EPSG:32635"


def test_a_garden_shed_read_from_a_file_has_no_interior_and_the_house_has_rooms():
    house, shed = map_city(load_map(Path(__file__).parents[1] / "data" / "maps" / "shed.osm")).masses
    assert shed.flags & FLAGS["FLAG_NO_INTERIOR"] and shed.height < house.height
    assert not house.flags & FLAGS["FLAG_NO_INTERIOR"]


def test_aerial_frustum_holds_every_building():
    map_data = block_map()
    city = map_city(map_data)
    camera = city.viewpoints["aerial"]
    corners = []
    for b in map_data.buildings:
        x0, y0, x1, y1 = b.outline.bounds
        for x, y in ((x0, y0), (x0, y1), (x1, y0), (x1, y1)):
            ((sx, sz),) = to_scene([(x, y)])
            corners += [(sx, 0.0, sz), (sx, b.height, sz)]
    clip = np.c_[np.array(corners), np.ones(len(corners))] @ camera.view_projection(16 / 9).T
    ndc = clip[:, :3] / clip[:, 3:4]
    assert np.all(clip[:, 3] > 0)
    assert np.all(np.abs(ndc) <= 1.0), np.abs(ndc).max(axis=0)
    # the cascaded shadows reach every building seen
    assert camera.shadow_far >= np.linalg.norm(np.array(corners) - camera.eye, axis=1).max()
    # framed, not lost in the picture: the buildings (150 m of the 250 m framed) span half the image or more
    assert np.ptp(ndc[:, 0]) > 0.9 or np.ptp(ndc[:, 1]) > 0.9


def test_street_camera_stands_on_a_residential_street_looking_along_it():
    map_data = block_map()
    camera = map_city(map_data).viewpoints["street"]
    assert camera.eye[1] == pytest.approx(1.7)
    x, y = camera.eye[0], -camera.eye[2]
    streets = [r for r in map_data.roads if r.kind == "residential"]  # walked streets before the avenue
    assert any(r.line.buffer(r.width / 2).contains(shapely.Point(x, y)) for r in streets)
    assert not any(b.outline.contains(shapely.Point(x, y)) for b in map_data.buildings)
    assert abs(camera.forward[2]) > 0.9  # the residential streets run north-south
    a, b = street_segment(map_data, [b.outline for b in map_data.buildings])
    assert a[0] == b[0] and a[0] in (45, 105)


def test_sun_matches_astral_at_helsinki_noon_midsummer():
    import datetime as dt

    from astral import Observer, sun

    when = dt.datetime(2025, 6, 21, 10, 0, tzinfo=dt.timezone.utc)  # 12:00 local standard time (UTC+2)
    position = sun_and_moon(HELSINKI, when)["sun"]
    observer = Observer(latitude=HELSINKI[1], longitude=HELSINKI[0])
    assert position == (pytest.approx(sun.elevation(observer, when)), pytest.approx(sun.azimuth(observer, when)))
    assert 50 < position[0] < 54 and 160 < position[1] < 185  # high in the south


def run_cli(*args) -> tuple[int, str]:
    import subprocess

    done = subprocess.run([sys.executable, "-m", "cityshade", *args], capture_output=True, text=True, timeout=600)
    return done.returncode, done.stdout + done.stderr


@pytest.mark.slow  # two command-line renders of Helsinki (make test-slow)
def test_render_map_cli_aerial_and_spot_camera(helsinki_pbf, tmp_path):
    for camera in ("aerial", "24.9449,60.1699,1.7,90"):
        out = tmp_path / "h.png"
        code, text = run_cli(
            "render",
            "--map",
            str(helsinki_pbf),
            "--camera",
            camera,
            "--size",
            "64x36",
            "--samples",
            "0",
            "--date",
            "2025-03-20",
            "--time",
            "12:00",
            "--out",
            str(out),
        )
        assert code == 0 and out.is_file(), text
        out.unlink()


@pytest.mark.parametrize(
    "option, value, words",
    [
        ("--camera", "24.9,60.1,tall,0", "lon,lat,height,heading"),
        ("--date", "2025-13-01", "YYYY-MM-DD"),
        ("--time", "25:00", "HH:MM"),
    ],
)
def test_render_map_cli_bad_values_one_line_exit_2(helsinki_pbf, tmp_path, option, value, words):
    out = tmp_path / "h.png"
    code, text = run_cli("render", "--map", str(helsinki_pbf), option, value, "--size", "32x18", "--out", str(out))
    assert code == 2 and words in text and len(text.strip().splitlines()) == 1, text
    assert not out.exists()


@pytest.mark.slow  # a video and a viewer of Helsinki (make test-slow)
def test_video_and_viewer_take_a_map(helsinki_pbf, tmp_path):
    from cityshade.commands.video import render_video
    from cityshade.maps import city_from_map, sky_clock
    from cityshade.render import RenderSettings
    from cityshade.viewer import open_viewer

    city, camera, placed = city_from_map(helsinki_pbf, "street", "2025-06-21", "21:00")
    assert camera == "street" and placed["sun"][0] < 10  # evening sun low over Helsinki
    sky = sky_clock(city.origin, "2025-06-21")
    out = render_video(
        tmp_path / "h.mp4",
        city,
        "walk",
        frames=2,
        fps=2,
        size=(64, 36),
        start_time="21:00",
        end_time="23:30",
        progress=False,
        sky=sky,
    )
    assert out.stat().st_size > 0
    viewer = open_viewer(city, camera, RenderSettings(samples=0, **placed), window="headless", size=(64, 36), sky=sky)
    try:
        viewer.press("T")  # a quarter of an hour later: the sun moves over the map
        assert viewer.renderer.settings.sun != placed["sun"]
        viewer.on_render(0.0, 0.016)
    finally:
        viewer.wnd.destroy()


def test_bench_osm_json_carries_methods_and_timing():
    from cityshade.bench.osm import OsmResult

    result = OsmResult(
        "device", methods={"helsinki_load_seconds": "how"}, timing={"samples_per_point": 4, "interleaved": True}
    )
    result.ratios["helsinki_load_seconds"] = 1.5
    payload = result.to_json()
    assert payload["timing"] == {"samples_per_point": 4, "interleaved": True}
    assert payload["methods"]["helsinki_load_seconds"] == "how" and payload["ratios"]["helsinki_load_seconds"] == 1.5


def test_helsinki_views_frame_the_city_and_stand_on_a_street(helsinki_pbf):
    from cityshade.maps import load_map

    map_data = load_map(helsinki_pbf)
    city = map_city(map_data)
    aerial = city.viewpoints["aerial"].view_projection(16 / 9)
    drawn = [b for b in map_data.buildings if b.drawn]
    corners = np.array([(x, 0.0, -y) for b in drawn for x, y in np.asarray(b.outline.exterior.coords)])
    clip = np.c_[corners, np.ones(len(corners))] @ aerial.T
    assert np.all(np.abs(clip[:, :3] / clip[:, 3:4]) <= 1.0)
    street = city.viewpoints["street"]
    eye = shapely.Point(street.eye[0], -street.eye[2])
    assert any(r.line.buffer(r.width / 2).contains(eye) for r in map_data.roads)
    assert not any(b.outline.contains(eye) for b in drawn)


def test_date_without_a_map_is_refused(tmp_path):
    code, text = run_cli("render", "--date", "2025-06-21", "--size", "32x18", "--out", str(tmp_path / "x.png"))
    assert code == 2 and "--map" in text and len(text.strip().splitlines()) == 1, text


def test_buildings_get_a_use_from_their_use_or_kind():
    from cityshade.maps.testing import use_code

    cases = {
        ("retail", "yes"): "shop",
        (None, "apartments"): "home",
        ("office", "yes"): "office",
        ("school", "yes"): "public",
        (None, "warehouse"): "industry",
        ("parking", "yes"): "mixed",
        (None, "yes"): "mixed",
    }
    for (use, kind), want in cases.items():
        assert use_code(types.SimpleNamespace(use=use, kind=kind)) == USES[want]
