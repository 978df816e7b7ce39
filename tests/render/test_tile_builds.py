"""Building a tile cache in parallel (`cityshade tile --workers K`, render/_tile_writer.py): the
per-tile function gives the same bytes whatever process runs it, the cache the same bytes whatever
order the tiles finish in, and a build that was stopped resumes from the tiles it kept."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest

from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.render import mesh_tile, run_here, write_tiles
from cityshade.scene import make_city

TILE = 64.0  # metres: the built-in district in 64 tiles, a few of them without buildings
TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"


def cache_bytes(folder: Path) -> dict:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def district():
    return make_city("default")


@pytest.fixture(scope="module")
def one_by_one(district, tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("one") / "tiles"
    summary = write_tiles(district, folder, tile_size=TILE)
    assert summary["resumed"] == 0 and summary["tiles"] > 8
    return cache_bytes(folder)


def backwards(function, shared, jobs):
    """A runner as another process would be: arguments and results through pickle, the last job first."""
    for key, *arguments in reversed(list(jobs)):
        shared_copy, arguments = pickle.loads(pickle.dumps((shared, arguments)))
        yield key, pickle.loads(pickle.dumps(function(*shared_copy, *arguments)))


class Collected(Exception):
    pass


def collect(function, shared, jobs):
    """A runner that runs nothing: the jobs write_tiles hands out."""
    raise Collected(shared, list(jobs))


def test_the_per_tile_function_gives_the_same_bytes_in_any_process(district, tmp_path):
    """mesh_tile on copies of its arguments (as a Ray task receives them through pickle) gives
    the tile's .npz bytes and its piece exactly."""
    with pytest.raises(Collected) as caught:
        write_tiles(district, tmp_path / "tiles", tile_size=TILE, run=collect)
    shared, jobs = caught.value.args
    assert len(jobs) > 8
    _, *arguments = jobs[3]
    here = mesh_tile(*shared, *arguments)
    there = pickle.loads(pickle.dumps(mesh_tile(*pickle.loads(pickle.dumps((*shared, *arguments))))))
    assert here.data is not None and here.data == there.data
    assert here.counts == there.counts and here.bounds == there.bounds and here.facades == there.facades
    for name in ("boxes", "cells", "records", "lod_faces"):
        assert getattr(here, name).tobytes() == getattr(there, name).tobytes(), name


def test_tiles_finishing_in_another_order_give_the_same_cache(district, one_by_one, tmp_path):
    folder = tmp_path / "tiles"
    write_tiles(district, folder, tile_size=TILE, run=backwards)
    assert cache_bytes(folder) == one_by_one


def test_a_stopped_build_resumes_from_the_tiles_it_kept(district, one_by_one, tmp_path):
    """Stopped after 5 tiles (as a kill or Ctrl-C stops it): the work folder keeps them; the next
    build of the same city meshes only the others and writes the same cache, then removes it."""
    folder = tmp_path / "tiles"
    meshed = []

    def stops_after_five(function, shared, jobs):
        for key, piece in run_here(function, shared, jobs):
            if len(meshed) == 5:
                raise KeyboardInterrupt
            meshed.append(key)
            yield key, piece

    with pytest.raises(KeyboardInterrupt):
        write_tiles(district, folder, tile_size=TILE, run=stops_after_five)
    assert not folder.exists() and (tmp_path / ".tiles.partial").is_dir()
    again = []

    def counting(function, shared, jobs):
        for key, piece in run_here(function, shared, jobs):
            again.append(key)
            yield key, piece

    summary = write_tiles(district, folder, tile_size=TILE, run=counting)
    assert summary["resumed"] == 5 and not set(again) & set(meshed)
    assert cache_bytes(folder) == one_by_one
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiles"]


def test_a_damaged_kept_tile_is_meshed_again(district, one_by_one, tmp_path):
    folder = tmp_path / "tiles"

    def stops_after_three(function, shared, jobs):
        for n, item in enumerate(run_here(function, shared, jobs)):
            if n == 3:
                raise KeyboardInterrupt
            yield item

    with pytest.raises(KeyboardInterrupt):
        write_tiles(district, folder, tile_size=TILE, run=stops_after_three)
    kept = sorted((tmp_path / ".tiles.partial").rglob("*.npz"))
    assert kept
    kept[0].write_bytes(kept[0].read_bytes()[:-10])  # a tile cut short
    write_tiles(district, folder, tile_size=TILE)
    assert cache_bytes(folder) == one_by_one


def test_another_city_does_not_resume_a_stopped_build(district, tmp_path):
    folder = tmp_path / "tiles"

    def stops(function, shared, jobs):
        for item in run_here(function, shared, jobs):
            yield item
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_tiles(district, folder, tile_size=TILE, run=stops)
    assert write_tiles(make_city("grid"), folder, tile_size=TILE)["resumed"] == 0


def test_a_folder_in_the_way_of_the_work_folder_is_never_removed(district, tmp_path):
    mine = tmp_path / ".tiles.partial"
    mine.mkdir()
    (mine / "notes.txt").write_text("not a build's")
    with pytest.raises(UsageError, match="is in the way of the build's work folder"):
        write_tiles(district, tmp_path / "tiles", tile_size=TILE)
    assert (mine / "notes.txt").read_text() == "not a build's"


def test_bad_worker_counts_are_one_line(capsys, tmp_path):
    for value in ("0", "many"):
        assert main(["tile", str(TAGGED), "--out", str(tmp_path / "t"), "--workers", value]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"cityshade: error: invalid --workers '{value}'") and "\n" not in err


@pytest.mark.slow  # starts a local Ray runtime
def test_two_ray_workers_write_the_bytes_of_one(tmp_path, capsys):
    one, two = tmp_path / "one", tmp_path / "two"
    assert main(["tile", str(TAGGED), "--out", str(one), "--tile-size", "64"]) == 0
    assert main(["tile", str(TAGGED), "--out", str(two), "--tile-size", "64", "--workers", "2"]) == 0
    assert "wrote" in capsys.readouterr().out
    assert cache_bytes(two) == cache_bytes(one)
