"""Streaming a tiled city (docs/scale.md, "Streaming"): the tile cache on disk, the same ids as the
whole city, frames that never wait for the tile reader, resident bytes under the budget, and bad
caches and budgets (one line, exit 2, or a rebuild with a notice)."""

from __future__ import annotations

import hashlib
import json
import os
import threading
import time
from argparse import Namespace
from pathlib import Path

import numpy as np
import pytest

from cityshade.commands import main
from cityshade.commands.tile import streamed_tiles
from cityshade.errors import CityshadeError, UsageError
from cityshade.interior import FACE_CODES
from cityshade.maps import load_map, map_city
from cityshade.render import CacheProblem, Renderer, RenderSettings, open_tiles, write_tiles
from cityshade.render._streaming import _Arena
from cityshade.render.testing import (
    GROUND_DTYPE,
    SLOT_UNIT,
    StreamedCityGPU,
    TileStreamer,
    ground_offset,
    ground_vertices,
    read_tile,
    slot_bytes,
)
from cityshade.scene import FACE_DTYPE, GPU_VERTEX_DTYPE, GROUND_LAND, Camera, expand_face_table, make_city, placements

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

MAPS = Path(__file__).parents[1] / "data" / "maps"
TAGGED, SHED = MAPS / "tagged.osm", MAPS / "shed.osm"
SIZE = (160, 120)
TILE = 64.0  # metres: the 329-building default city in 64 tiles
COLOUR_TOLERANCE = 2  # of 255: the ground is drawn in another order, its pixels shaded alike
PARTS = {"vertices": GPU_VERTEX_DTYPE, "faces": FACE_DTYPE, "ground": GROUND_DTYPE}  # a tile's, in its slot's order


@pytest.fixture(scope="module")
def district():
    return make_city("default")


@pytest.fixture(scope="module")
def district_tiles(district, tmp_path_factory):
    folder = tmp_path_factory.mktemp("district") / "tiles"
    write_tiles(district, folder, tile_size=TILE)
    return open_tiles(folder)


@pytest.fixture(scope="module")
def tagged_city():
    return map_city(load_map(TAGGED))


@pytest.fixture(scope="module")
def tagged_small_tiles(tagged_city, tmp_path_factory):
    """The tagged map in tiles of TILE metres: its five buildings in five tiles, with their ground."""
    folder = tmp_path_factory.mktemp("tagged") / "tiles"
    write_tiles(tagged_city, folder, tile_size=TILE)
    return open_tiles(folder)


@pytest.fixture()
def tagged_tiles(tmp_path):
    folder = tmp_path / "tiles"
    assert main(["tile", str(TAGGED), "--out", str(folder)]) == 0
    return folder


def one_line_error(capsys, argv) -> str:
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert err.count("\n") == 0 and err.startswith("cityshade: error: ") and "Traceback" not in err
    return err


def nearest_first(tiles, eye) -> list[int]:
    return sorted(range(len(tiles)), key=lambda i: (tiles[i].distance(eye[0], eye[2]), i))


# -- the cache -------------------------------------------------------------------------------------


def test_tile_writes_manifest_tiles_and_a_summary(tmp_path, capsys):
    folder = tmp_path / "cache"
    assert main(["tile", str(TAGGED), "--out", str(folder)]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1 and out[0].startswith(f"wrote {folder}: ") and " tiles, " in out[0] and " s" in out[0]
    manifest = json.loads((folder / "manifest.json").read_text())
    data = TAGGED.read_bytes()
    assert manifest["source"] == {"name": TAGGED.name, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}
    assert manifest["format"] == 2 and manifest["cityshade"] and manifest["tiles"]
    for tile in manifest["tiles"]:
        path = folder / tile["file"]
        assert path.stat().st_size == tile["bytes"]
        assert tile["resident_bytes"] == slot_bytes(tile["vertices"], tile["faces"], tile["ground"])
        held = sum(tile[part] * dtype.itemsize for part, dtype in PARTS.items())
        assert held <= tile["resident_bytes"] < held + FACE_DTYPE.itemsize + GROUND_DTYPE.itemsize + SLOT_UNIT
        x0, z0, x1, z1 = tile["bounds"]
        assert x0 <= x1 and z0 <= z1
    assert sorted(p.name for p in folder.iterdir()) == [".cityshade-output", "city.pickle", "manifest.json", "tiles"]
    marker = json.loads((folder / ".cityshade-output").read_text())
    written = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    assert marker == {"kind": "tile-cache", "format": 1, "files": [n for n in written if n != ".cityshade-output"]}


def test_tiles_hold_every_building_once(district, district_tiles):
    cache = district_tiles
    placement = placements(district.masses)
    vertices = [expand_face_table(*read_tile(cache, i)[:2], placement) for i in range(len(cache.tiles))]
    assert sum(t.buildings for t in cache.tiles) == len(cache.boxes) == len(district.masses)
    held = np.concatenate([np.unique(v["ids"][:, 0]) for v in vertices])
    assert sorted(held.tolist()) == sorted(cache.boxes["draw"][:, 2].tolist())
    for i, v in enumerate(vertices):  # each box's range within its tile holds its building only
        for box in cache.boxes[cache.box_tile == i]:
            count, first, building = (int(x) for x in box["draw"][:3])
            assert np.all(v["ids"][first : first + count, 0] == building)


def test_tiles_hold_the_ground_of_their_cells(tagged_city, tagged_small_tiles):
    """Every ground triangle once, in the whole city's order: the tiles' (those in a cell with
    buildings, no wider than a tile) and the city's own (the rest, and the land under the map,
    which no tile holds: a tile away leaves no hole in it)."""
    cache = tagged_small_tiles
    whole = ground_vertices(tagged_city).reshape(-1, 12)
    base = ground_vertices(cache.city).reshape(-1, 12)
    tiled = [read_tile(cache, i)[2].reshape(-1, 12) for i in range(len(cache.tiles))]
    assert sum(map(len, tiled)) + len(base) == len(whole) and sum(map(len, tiled)) and len(base)
    assert all(np.all(np.ptp(part[:, [0, 4, 8]], axis=1) <= TILE) for part in tiled)
    assert not any(np.any(part[:, 3] == GROUND_LAND) for part in tiled)
    assert np.count_nonzero(whole[:, 3] == GROUND_LAND) == np.count_nonzero(base[:, 3] == GROUND_LAND) > 0
    position = {row.tobytes(): i for i, row in enumerate(whole)}
    assert len(position) == len(whole)  # no triangle twice, so each is found by its bytes
    found = [np.array([position[row.tobytes()] for row in part], int) for part in (*tiled, base)]
    assert sorted(np.concatenate(found).tolist()) == list(range(len(whole)))
    assert all(np.all(np.diff(part) > 0) for part in found)


# -- drawing ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("culling", ["gpu", "off"])
def test_streamed_ids_equal_the_whole_city(district, district_tiles, gl_context, culling):
    """With a budget that holds every tile whose buildings the view shows (nearest first) but not
    the whole city, the id AOV is the whole city's, pixel for pixel."""
    cache, camera = district_tiles, district.camera("street")
    renderer = Renderer(SIZE, RenderSettings(samples=0, culling=culling), ctx=gl_context)
    try:
        renderer.set_city(district)
        whole = renderer.render_ids(camera)
        seen = np.unique(whole[..., 2][whole[..., 2] > 0]) - 1
        needed = set(cache.box_tile[np.isin(cache.boxes["draw"][:, 2], seen)].tolist())
        order = nearest_first(cache.tiles, camera.eye)
        prefix = order[: max(order.index(i) for i in needed) + 1]
        budget = sum(cache.tiles[i].resident_bytes for i in prefix)
        assert budget < cache.total_bytes  # some tiles stay on disk
        renderer.set_tiles(cache, budget)
        renderer.wait_for_tiles(camera)
        assert set(renderer.city.streamer.resident) == set(prefix)
        streamed = renderer.render_ids(camera)
    finally:
        renderer.release()
    differing = int(np.count_nonzero(np.any(streamed != whole, axis=-1)))
    assert differing == 0, f"{differing} of {whole.shape[0] * whole.shape[1]} pixels differ"
    assert np.count_nonzero(whole[..., 2]) > 0.2 * whole.shape[0] * whole.shape[1]


@pytest.mark.parametrize("low", [False, True])
def test_streamed_ground_looks_as_the_whole_city(tagged_city, tagged_small_tiles, gl_context, low):
    """Every tile resident, the ground drawn from the tiles' slots after the triangles no tile holds:
    the same ids (materials, lamp lists) and the same colours as the whole city's ground, from the
    map's aerial camera and from 2 m above its target, looking across the ground."""
    camera = tagged_city.camera("aerial")
    if low:
        x, _, z = camera.target
        camera = Camera((x - 60.0, 2.0, z - 60.0), camera.target)
    renderer = Renderer(SIZE, RenderSettings(samples=0), ctx=gl_context)
    try:
        renderer.set_city(tagged_city)
        whole, whole_ids = renderer.render(camera), renderer.render_ids(camera)
        renderer.set_tiles(tagged_small_tiles)
        renderer.wait_for_tiles(camera)
        streamed, streamed_ids = renderer.render(camera), renderer.render_ids(camera)
    finally:
        renderer.release()
    ground = np.count_nonzero(whole_ids[..., 0] == FACE_CODES["FACE_GROUND"])
    assert ground > 0.2 * whole_ids.shape[0] * whole_ids.shape[1]
    differing = int(np.count_nonzero(np.any(streamed_ids != whole_ids, axis=-1)))
    assert differing == 0, f"ids: {differing} of {ground} ground pixels differ"
    off = np.abs(streamed.astype(int) - whole.astype(int)).max(axis=-1)
    assert int(np.count_nonzero(off > COLOUR_TOLERANCE)) == 0, (
        f"colours: {np.count_nonzero(off)} pixels differ, by {off.max()}"
    )


def test_tiles_away_leave_no_hole_in_the_ground(tagged_city, tagged_tiles, gl_context):
    """Only the nearest tile resident, from the air: where the whole city shows anything, the
    streamed one shows the ground or a building, never the sky below the horizon (tiles of the
    default size, which the land's cells under a map would fit)."""
    cache, camera = open_tiles(tagged_tiles), tagged_city.camera("aerial")
    assert len(cache.tiles) > 1
    nearest = nearest_first(cache.tiles, camera.eye)[0]
    renderer = Renderer(SIZE, RenderSettings(samples=0), ctx=gl_context)
    try:
        renderer.set_city(tagged_city)
        whole = renderer.render_ids(camera)
        renderer.set_tiles(cache, cache.tiles[nearest].resident_bytes)
        renderer.wait_for_tiles(camera)
        assert set(renderer.city.streamer.resident) == {nearest}
        streamed = renderer.render_ids(camera)
    finally:
        renderer.release()
    holes = int(np.count_nonzero((whole[..., 0] != 0) & (streamed[..., 0] == 0)))
    assert holes == 0, f"{holes} pixels show the sky through the ground"
    assert np.count_nonzero(np.any(streamed != whole, axis=-1)) > 0  # tiles are away


def test_frames_never_wait_for_the_tile_reader(district, district_tiles, gl_context):
    """A reader held back: frames keep being drawn (with no buildings) while it reads; once it has
    read, the next frames upload the tiles and draw them."""
    cache, camera = district_tiles, district.camera("street")
    go = threading.Event()

    def held_back(index):
        assert go.wait(60), "never released"
        return read_tile(cache, index)

    renderer = Renderer((32, 24), RenderSettings(samples=0), ctx=gl_context)
    try:
        renderer.set_city(district)
        renderer.draw(camera)  # compiles the programs
        renderer.set_tiles(cache, cache.total_bytes // 2, read=held_back)
        streamer = renderer.city.streamer
        for _ in range(3):
            renderer.draw(camera)
            ids = renderer.render_ids(camera)
            assert streamer.reading and not streamer.resident
            assert np.count_nonzero(ids[..., 2]) == 0  # nothing resident, nothing drawn
        go.set()
        deadline = time.monotonic() + 60
        while not streamer.complete(camera.eye[0], camera.eye[2]) and time.monotonic() < deadline:
            renderer.draw(camera)
            time.sleep(0.01)
        ids = renderer.render_ids(camera)
    finally:
        go.set()
        renderer.release()
    assert streamer.resident and np.count_nonzero(ids[..., 2]) > 0


def held_tiles(city: StreamedCityGPU, placement) -> dict[int, np.ndarray]:
    """Each resident tile's vertices as the vertex stage gets them from its slot of the arena (the
    vertices there, read through the face rows they point at, and the ground)."""
    size = GPU_VERTEX_DTYPE.itemsize
    table = np.frombuffer(city.faces.read(), np.uint8)
    table = table[: len(table) // FACE_DTYPE.itemsize * FACE_DTYPE.itemsize].view(FACE_DTYPE)
    held = {}
    for index, (first, _) in city.arena.slots.items():
        tile = city.streamer.tiles[index]
        vertices = city.building_vbo.read(size=tile.vertices * size, offset=first * SLOT_UNIT)
        ground_at = first * SLOT_UNIT + ground_offset(tile.vertices, tile.faces)
        ground = (
            city.building_vbo.read(size=tile.ground * GROUND_DTYPE.itemsize, offset=ground_at) if tile.ground else b""
        )
        held[index] = (expand_face_table(np.frombuffer(vertices, GPU_VERTEX_DTYPE), table, placement).tobytes(), ground)
    return held


def tile_as_drawn(cache, index: int, placement) -> tuple[bytes, bytes]:
    vertices, faces, ground = read_tile(cache, index)
    return expand_face_table(vertices, faces, placement).tobytes(), ground.tobytes()


def test_resident_bytes_stay_under_the_budget_along_a_path(district, district_tiles, gl_context):
    """Walking across the city: at every step the resident tiles (uploaded and being read) fit the
    budget, tiles are released behind the camera, and each resident tile's slot of the arena holds
    its vertices and face rows."""
    cache = district_tiles
    budget = cache.total_bytes // 4
    placement = placements(district.masses)
    city = StreamedCityGPU(gl_context, cache, budget)
    released = set()
    try:
        assert city.arena.capacity * SLOT_UNIT <= budget
        x0, z0, x1, z1 = district.bounds
        for t in np.linspace(0, 1, 12):
            eye = (x0 + t * (x1 - x0), 2.0, z0 + t * (z1 - z0))
            before = set(city.streamer.resident)
            city.follow(eye)
            assert city.streamer.resident_bytes <= budget
            city.wait(eye)
            released |= before - set(city.streamer.resident)
            assert city.streamer.resident_bytes <= budget
            for index, held in held_tiles(city, placement).items():
                assert held == tile_as_drawn(cache, index, placement)
        assert city.streamer.peak_bytes <= budget
    finally:
        city.release()
    assert released


def test_compacting_the_arena_moves_face_rows_and_ground_with_their_vertices(
    tagged_city, tagged_small_tiles, gl_context
):
    """Slots moved down to close the gaps: each tile's vertices point at their rows where they are
    now, and its ground is drawn from where it is now."""
    cache, placement = tagged_small_tiles, placements(tagged_city.masses)
    city = StreamedCityGPU(gl_context, cache)
    try:
        city.wait(tagged_city.camera("aerial").eye)
        for index in list(city.arena.slots)[::2]:  # every other slot freed: gaps between the rest
            city.streamer.resident.pop(index)
            city._release_tile(index)
        before = {index: first for index, (first, _) in city.arena.slots.items()}
        city.arena.compact()
        assert any(city.arena.slots[index][0] < first for index, first in before.items())
        city._moved_boxes()
        for index, held in held_tiles(city, placement).items():
            assert held == tile_as_drawn(cache, index, placement)
            count, _, first = city._ground_draws[index, :3].tolist()
            size = GROUND_DTYPE.itemsize
            assert count == cache.tiles[index].ground
            assert (city.building_vbo.read(size=count * size, offset=first * size) if count else b"") == held[1]
    finally:
        city.release()


def test_update_never_waits_for_a_slow_read(district_tiles):
    cache = district_tiles
    reading, release = threading.Event(), threading.Event()

    def slow(index):
        reading.set()
        release.wait(60)  # held until the frames below have run (a bound, so a fault fails, never hangs)
        return read_tile(cache, index)

    loaded = []
    streamer = TileStreamer(cache.tiles, cache.total_bytes, slow, lambda i, v: loaded.append(i), lambda i: None)
    try:
        streamer.update(0.0, 0.0)
        assert reading.wait(60), "no tile read was started"
        for _ in range(20):  # frames while the read is held: each returns without its tile
            streamer.update(0.0, 0.0)
        assert not loaded
        release.set()
        for _ in range(6000):
            streamer.update(0.0, 0.0)
            if loaded:
                break
            time.sleep(0.01)
    finally:
        release.set()
        streamer.close()
    assert loaded  # the tile arrived once its read finished


def test_arena_compacts_when_no_gap_is_wide_enough(gl_context):
    moves = []
    size = 24
    arena = _Arena(gl_context, 30, size, lambda *move: moves.append(move))
    data = {k: np.full(10 * size, k, np.uint8).tobytes() for k in range(3)}
    for k in range(3):
        arena.buffer.write(data[k], offset=arena.allocate(k, 10) * size)
    arena.free(0)
    arena.free(2)
    first = arena.allocate(3, 20)  # 20 free, in two gaps of 10
    assert arena.slots[1] == (0, 10) and first == 10 and moves == [(1, 10, 0)]
    assert arena.buffer.read(size=10 * size, offset=0) == data[1]
    arena.buffer.release()


# -- bad input -------------------------------------------------------------------------------------


def test_a_budget_too_small_for_the_nearest_tile_is_one_line(tagged_tiles, tmp_path, capsys):
    err = one_line_error(
        capsys, ["render", "--tiles", str(tagged_tiles), "--memory-budget", "1KB", "--out", str(tmp_path / "a.png")]
    )
    assert "memory budget 1.0 KB is too small for the nearest tile (tiles/" in err and "or more" in err
    assert not (tmp_path / "a.png").exists()


@pytest.mark.parametrize("text", ["lots", "0MB", "-1GB", "12XB"])
def test_a_bad_budget_is_one_line(text, tmp_path, capsys):
    err = one_line_error(capsys, ["render", f"--memory-budget={text}", "--out", str(tmp_path / "a.png")])
    assert f"--memory-budget {text!r}" in err


def _set_version(folder: Path):
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["cityshade"] = "0.0.1"
    (folder / "manifest.json").write_text(json.dumps(manifest))


def _set_code(folder: Path):
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["meshing_code"] = "0123456789abcdef"
    (folder / "manifest.json").write_text(json.dumps(manifest))


def _garbage_manifest(folder: Path):
    (folder / "manifest.json").write_bytes(b"\x00garbage{")


def _truncated_tile(folder: Path):
    path = folder / "tiles" / "00000.npz"
    path.write_bytes(path.read_bytes()[:100])


def _truncated_city(folder: Path):
    path = folder / "city.pickle"
    path.write_bytes(path.read_bytes()[:-10])


DAMAGE = {
    "version": (_set_version, "made with cityshade '0.0.1'"),
    "code": (_set_code, "made with meshing_code '0123456789abcdef'"),
    "manifest": (_garbage_manifest, "manifest.json is damaged"),
    "tile": (_truncated_tile, "tiles/00000.npz is missing or damaged"),
    "city": (_truncated_city, "city.pickle is damaged"),
}


@pytest.mark.parametrize("damage", DAMAGE)
def test_a_stale_or_damaged_cache_without_its_source_is_one_line(damage, tagged_tiles, tmp_path, capsys):
    spoil, reason = DAMAGE[damage]
    spoil(tagged_tiles)
    err = one_line_error(capsys, ["render", "--tiles", str(tagged_tiles), "--out", str(tmp_path / "a.png")])
    assert reason in err and "cityshade tile SOURCE --out" in err


@pytest.mark.parametrize("damage", DAMAGE)
def test_a_stale_or_damaged_cache_is_made_again_from_its_source(damage, tagged_tiles, capsys):
    spoil, reason = DAMAGE[damage]
    spoil(tagged_tiles)
    args = Namespace(map=TAGGED, tiles=tagged_tiles, memory_budget=None)
    with streamed_tiles(args) as (cache, budget):
        assert cache.source["sha256"] == hashlib.sha256(TAGGED.read_bytes()).hexdigest()
    out = capsys.readouterr()
    notices = out.err.strip().splitlines()
    assert len(notices) == 1 and reason in notices[0] and "making it again from" in notices[0]
    assert out.out.startswith("tile cache made in ")
    open_tiles(tagged_tiles)  # whole again


def test_a_cache_of_another_file_is_made_again(tagged_tiles, capsys):
    args = Namespace(map=SHED, tiles=tagged_tiles, memory_budget="1GB")
    with streamed_tiles(args) as (cache, budget):
        assert cache.source["name"] == SHED.name and budget == 10**9
    notice = capsys.readouterr().err.splitlines()[0]
    assert "made from another file ('tagged.osm'" in notice
    with pytest.raises(CacheProblem, match="another file"):
        open_tiles(tagged_tiles, {"name": TAGGED.name, "bytes": 1, "sha256": "0"})


def test_an_altered_tile_fails_when_read(tagged_tiles, tmp_path, capsys):
    """Same size, other bytes: the reader's SHA-256 check stops it, one line, before any frame."""
    path = tagged_tiles / "tiles" / "00000.npz"
    data = bytearray(path.read_bytes())
    data[-1] ^= 0xFF
    path.write_bytes(bytes(data))
    err = one_line_error(capsys, ["render", "--tiles", str(tagged_tiles), "--out", str(tmp_path / "a.png")])
    assert "tiles/00000.npz is damaged (its SHA-256 is not the manifest's)" in err
    with pytest.raises(CityshadeError):
        read_tile(open_tiles(tagged_tiles), 0)


def _rewritten_tile(folder: Path, **arrays):
    """Tile 0's file replaced by `arrays`, its size and SHA-256 in the manifest to match."""
    path = folder / "tiles" / "00000.npz"
    np.savez(path, **arrays)
    data = path.read_bytes()
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["tiles"][0].update(bytes=len(data), sha256=hashlib.sha256(data).hexdigest())
    (folder / "manifest.json").write_text(json.dumps(manifest))


@pytest.mark.parametrize(
    "arrays, reason",
    [
        ("no faces", "cannot be read (KeyError"),
        ("rows beyond", "has vertices of face rows it does not hold"),
        ("vertices as faces", "holds faces of another layout or count than its tile's"),
        ("ground of another layout", "holds ground of another layout or count than its tile's"),
    ],
)
def test_a_tile_file_of_other_contents_is_one_line(arrays, reason, tagged_tiles, tmp_path, capsys):
    """A tile file whose manifest entry matches but whose arrays are not its tile's: refused when read."""
    vertices, faces, ground = read_tile(open_tiles(tagged_tiles), 0)
    if arrays == "no faces":
        _rewritten_tile(tagged_tiles, vertices=vertices, ground=ground, other=faces)  # as large, no faces.npy
    elif arrays == "rows beyond":
        vertices["face"][-1] = len(faces)
        _rewritten_tile(tagged_tiles, vertices=vertices, faces=faces, ground=ground)
    elif arrays == "ground of another layout":
        _rewritten_tile(tagged_tiles, vertices=vertices, faces=faces, ground=ground.astype(np.float64))
    else:
        _rewritten_tile(tagged_tiles, vertices=vertices, faces=vertices, ground=ground)
    err = one_line_error(capsys, ["render", "--tiles", str(tagged_tiles), "--out", str(tmp_path / "a.png")])
    assert f"tiles/00000.npz {reason}" in err
    assert not (tmp_path / "a.png").exists()


def _edit_manifest(folder: Path, change):
    manifest = json.loads((folder / "manifest.json").read_text())
    change(manifest)
    (folder / "manifest.json").write_text(json.dumps(manifest))


def _refused(folder: Path, tile: int | None = None) -> str:
    """The one line that opening the cache (and reading `tile`) fails with."""
    with pytest.raises(CacheProblem) as failure:
        cache = open_tiles(folder)
        if tile is not None:
            read_tile(cache, tile)
    assert "\n" not in str(failure.value)
    return str(failure.value)


@pytest.mark.parametrize("name", ["manifest.json", "city.pickle", "tiles/00000.npz"])
@pytest.mark.parametrize("kind", ["fifo", "/dev/zero"])
def test_cache_files_that_are_not_regular_files_are_one_line(name, kind, tagged_tiles):
    path = tagged_tiles / name
    path.unlink()
    if kind == "fifo":
        os.mkfifo(path)
    else:
        path.symlink_to(kind)
    assert name in _refused(tagged_tiles, 0)


@pytest.mark.parametrize(
    "text", ["[" * 100_000, '{"tiles": ' + "[" * 50 + "]" * 50 + "}"], ids=["past the parser", "tiles 50 deep"]
)
def test_a_deeply_nested_manifest_is_one_line(text, tagged_tiles):
    (tagged_tiles / "manifest.json").write_text(text)
    assert "manifest.json is damaged" in _refused(tagged_tiles)


def test_files_the_manifest_names_outside_the_cache_are_refused_unsized(tagged_tiles, tmp_path):
    secret = tmp_path / "secret.bin"
    secret.write_bytes(b"s" * 12345)
    for name in ("../secret.bin", str(secret), "tiles/../../secret.bin"):
        _edit_manifest(tagged_tiles, lambda m, name=name: m["tiles"][0].update(file=name))
        reason = _refused(tagged_tiles)
        assert "tile 0's file is not a name like tiles/00000.npz" in reason and "12345" not in reason
    _edit_manifest(tagged_tiles, lambda m: m["tiles"][0].update(file="tiles/00000.npz"))
    (tagged_tiles / "tiles" / "00000.npz").unlink()
    (tagged_tiles / "tiles" / "00000.npz").symlink_to(secret)
    reason = _refused(tagged_tiles)
    assert "tiles/00000.npz leads outside the cache" in reason and "12345" not in reason and "secret" not in reason


@pytest.mark.parametrize(
    "change, reason",
    [
        (lambda m: m["tiles"][0].update(bytes=float("inf")), "tile 0's bytes is not a whole number"),
        (lambda m: m["tiles"][0].update(vertices=-1), "tile 0's vertices is not a whole number"),
        (lambda m: m["tiles"][0].update(faces="12"), "tile 0's faces is not a whole number"),
        (lambda m: m["tiles"][0].update(ground=10**30), "tile 0's ground is not a whole number"),
        (lambda m: m["tiles"][0].update(vertices=10**9), "tile 0's counts need more bytes than its file has"),
        (lambda m: m["tiles"][0].update(bounds=[0, 0, float("nan"), 1]), "tile 0's bounds are not four finite"),
        (lambda m: m["tiles"][0].update(sha256=None), "tile 0's sha256 is not 64 hexadecimal digits"),
        (lambda m: m["tiles"].append([]), "is not an object"),
        (lambda m: m.update(tiles={"a": 1}), "its tiles are not a list"),
        (lambda m: m.update(city="/etc/passwd"), "its city is not city.pickle"),
        (lambda m: m["city"].update(bytes=True), "the city's bytes is not a whole number"),
        (lambda m: m.update(cityshade=["x"] * 10**5), "made with cityshade of another kind, this cityshade needs"),
    ],
)
def test_hostile_manifest_values_are_one_line(change, reason, tagged_tiles):
    _edit_manifest(tagged_tiles, change)
    assert reason in _refused(tagged_tiles)


def _rewritten_city(folder: Path, change):
    """city.pickle with `change` made to its parts, its size and SHA-256 in the manifest to match."""
    import pickle

    path = folder / "city.pickle"
    rest = pickle.loads(path.read_bytes())
    change(rest)
    data = pickle.dumps(rest)
    path.write_bytes(data)
    _edit_manifest(folder, lambda m: m["city"].update(bytes=len(data), sha256=hashlib.sha256(data).hexdigest()))


@pytest.mark.parametrize(
    "change, reason",
    [
        (lambda rest: rest["box_tile"].__setitem__(0, 99), "has boxes of tiles the manifest does not list"),
        (lambda rest: rest["boxes"]["draw"].__setitem__((0, 1), 10**6), "has boxes of vertices or buildings"),
        (lambda rest: rest.pop("records"), "is not a tile cache's city"),
    ],
)
def test_a_city_whose_boxes_name_other_tiles_is_one_line(change, reason, tagged_tiles):
    _rewritten_city(tagged_tiles, change)
    assert f"city.pickle {reason}" in _refused(tagged_tiles)


def _tile_with_faces(folder: Path, write_faces):
    """Tile 0 rewritten with its vertices and ground and a faces.npy that `write_faces(archive,
    faces)` writes (`faces`: its rows as they were), the manifest made to match the file."""
    import io
    import zipfile

    vertices, faces, ground = read_tile(open_tiles(folder), 0)
    stream = io.BytesIO()
    with zipfile.ZipFile(stream, "w") as archive:
        for name, array in (("vertices", vertices), ("ground", ground)):
            with archive.open(f"{name}.npy", "w") as member:
                np.lib.format.write_array(member, array)
        write_faces(archive, faces)
    data = stream.getvalue()
    (folder / "tiles" / "00000.npz").write_bytes(data)
    _edit_manifest(folder, lambda m: m["tiles"][0].update(bytes=len(data), sha256=hashlib.sha256(data).hexdigest()))


def _faces_header(member, faces: np.ndarray, shape: tuple):
    header = {"descr": np.lib.format.dtype_to_descr(faces.dtype), "fortran_order": False, "shape": shape}
    np.lib.format.write_array_header_1_0(member, header)


def test_a_tile_header_larger_than_its_tile_is_refused_before_allocating(tagged_tiles):
    """A faces.npy of a header alone claiming 10**12 rows (and the bytes its rows would take in
    another member): refused from the header, before 10**12 rows are allocated."""

    def huge(archive, faces):
        with archive.open("faces.npy", "w") as member:
            _faces_header(member, faces, (10**12,))
        archive.writestr("padding", bytes(faces.nbytes))

    _tile_with_faces(tagged_tiles, huge)
    assert "tiles/00000.npz holds faces of another layout or count than its tile's" in _refused(tagged_tiles, 0)


def test_a_tile_member_cut_short_after_its_header_is_one_line(tagged_tiles):
    """A faces.npy whose header is its tile's but whose rows stop half-way (the manifest made to
    match the file): refused, not read as a shorter table."""

    def cut_short(archive, faces):
        with archive.open("faces.npy", "w") as member:
            _faces_header(member, faces, faces.shape)
            member.write(faces.tobytes()[: faces.nbytes // 2])

    _tile_with_faces(tagged_tiles, cut_short)
    assert "tiles/00000.npz cannot be read (EOFError: faces.npy is cut short)" in _refused(tagged_tiles, 0)


class _Payload:
    """Unpickles by calling os.system: what a cache folder from elsewhere could hold."""

    def __init__(self, marker: Path):
        self.marker = marker

    def __reduce__(self):
        import os

        return os.system, (f"touch {self.marker}",)


def test_a_cache_whose_city_calls_a_function_is_refused_unrun(tagged_tiles, tmp_path, capsys):
    """A city.pickle naming os.system, with a manifest whose SHA-256 matches it: refused in one
    line, and the command never runs."""
    import pickle

    marker = tmp_path / "ran"
    data = pickle.dumps({"city": _Payload(marker)})
    (tagged_tiles / "city.pickle").write_bytes(data)
    manifest = json.loads((tagged_tiles / "manifest.json").read_text())
    manifest["city"].update(bytes=len(data), sha256=hashlib.sha256(data).hexdigest())
    (tagged_tiles / "manifest.json").write_text(json.dumps(manifest))
    err = one_line_error(capsys, ["render", "--tiles", str(tagged_tiles), "--out", str(tmp_path / "a.png")])
    assert "city.pickle refers to posix.system" in err or "city.pickle refers to os.system" in err
    assert not marker.exists()


def test_the_viewer_streams_and_shows_its_tiles(district_tiles):
    from cityshade.viewer import open_viewer

    budget = district_tiles.total_bytes // 2
    viewer = open_viewer(
        settings=RenderSettings(samples=0),
        window="headless",
        size=(64, 48),
        target_fps=None,
        tiles=district_tiles,
        memory_budget=budget,
    )
    try:
        streamer = viewer.renderer.city.streamer
        deadline = time.monotonic() + 60
        while not streamer.resident and time.monotonic() < deadline:
            viewer.wnd.use()
            viewer.on_render(0.0, 0.05)
        assert streamer.resident and streamer.resident_bytes <= budget
        assert f"tiles {len(streamer.resident)}/{len(district_tiles.tiles)} " in viewer.wnd.title
    finally:
        viewer.renderer.release()
        viewer.wnd.destroy()


def test_the_viewer_refuses_a_budget_below_the_nearest_tile(district_tiles):
    from cityshade.viewer import open_viewer

    with pytest.raises(UsageError, match="too small for the nearest tile"):
        open_viewer(window="headless", size=(64, 48), tiles=district_tiles, memory_budget=100)


def test_a_failed_write_leaves_the_old_cache_whole(tagged_tiles, monkeypatch):
    """An error (or a signal, which the command turns into one) half-way through writing tiles:
    the folder still holds the old cache, and beside it only the build's work folder is left
    (for the next build to resume from: tests/render/test_tile_builds.py)."""
    from cityshade.render import _tile_writer

    before = {p.relative_to(tagged_tiles): p.read_bytes() for p in tagged_tiles.rglob("*") if p.is_file()}

    def fail(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(_tile_writer, "mesh_tile", fail)
    with pytest.raises(KeyboardInterrupt):
        write_tiles(make_city("default"), tagged_tiles)
    after = {p.relative_to(tagged_tiles): p.read_bytes() for p in tagged_tiles.rglob("*") if p.is_file()}
    assert after == before
    assert sorted(p.name for p in tagged_tiles.parent.iterdir()) == [".tiles.partial", "tiles"]
    open_tiles(tagged_tiles)


def test_a_folder_of_something_else_is_never_replaced(tmp_path, capsys):
    other = tmp_path / "photos"
    other.mkdir()
    (other / "cat.jpg").write_bytes(b"not a cache")
    err = one_line_error(capsys, ["tile", str(TAGGED), "--out", str(other)])
    assert "is not an earlier output of this command" in err
    err = one_line_error(
        capsys, ["render", "--map", str(TAGGED), "--tiles", str(other), "--out", str(tmp_path / "a.png")]
    )
    assert "is not an earlier output of this command" in err
    assert [p.name for p in other.iterdir()] == ["cat.jpg"]


@pytest.mark.parametrize(
    "args, message",
    [
        (["--tile-size", "-3"], "invalid --tile-size '-3'"),
        (["--tile-size", "abc"], "invalid --tile-size 'abc'"),
        ([], "not a readable OpenStreetMap file"),
    ],
)
def test_tile_refuses_garbage_in_one_line_and_writes_nothing(args, message, tmp_path, capsys):
    source = tmp_path / "garbage.osm.pbf"
    source.write_bytes(b"garbage<<")
    out = tmp_path / "tiles"
    err = one_line_error(capsys, ["tile", str(source), "--out", str(out), *args])
    assert message in err
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["garbage.osm.pbf"]
