"""Fuzzers of folder outputs: damaged tile caches, hostile output markers and export options. A
small budget runs with every `make test`; `make fuzz` runs the `fuzz`-marked tests for
CITYSHADE_FUZZ_SECONDS seconds each (docs/robustness.md). Each property: a valid result or one
line (UsageError, exit code 2), never another exception, nothing outside the folder read, quoted
or deleted."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from cityshade._files import OUTPUT_MARKER, atomic_folder
from cityshade.errors import UsageError
from cityshade.export import FORMATS, check_output, crop, map_export_city, parse_region
from cityshade.maps import load_map, map_city
from cityshade.render import CacheProblem, _tile_cache, open_tiles, write_tiles
from cityshade.render.testing import read_tile
from fuzzing import LARGE, SMALL, for_a_while

TAGGED = Path(__file__).parents[1] / "data" / "maps" / "tagged.osm"
SECRET = b"s" * 4321  # a file beside the folder: never read, quoted or sized

# ------------------------------------------------------------------ damaged tile caches

hostile_scalar = st.one_of(
    st.integers(-(10**30), 10**30),
    st.floats(),
    st.just(1e308),
    st.booleans(),
    st.none(),
    st.text(max_size=6),
    st.sampled_from(["../secret.bin", "/etc/passwd", "tiles/../../secret.bin", "tiles/00000.npz", "city.pickle"]),
)
hostile_json = st.recursive(
    hostile_scalar,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=12,
)
TILE_KEYS = ["file", "bounds", "buildings", "vertices", "faces", "ground", "bytes", "sha256"]


@st.composite
def manifest_damage(draw):
    """A list of edits: (where, value), where is a key of the manifest, its city or a tile."""
    edits = []
    for _ in range(draw(st.integers(1, 4))):
        where = draw(
            st.one_of(
                st.tuples(st.just("tile"), st.integers(0, 5), st.sampled_from(TILE_KEYS)),
                st.tuples(st.just("city"), st.sampled_from(["file", "bytes", "sha256"])),
                st.tuples(st.just("top"), st.sampled_from(["tiles", "city", "format", "source", "cityshade"])),
                st.tuples(st.just("nest"), st.integers(1, 3000)),
            )
        )
        edits.append((where, draw(hostile_json)))
    return edits


def _apply(manifest: dict, where: tuple, value):
    if where[0] == "tile" and isinstance(manifest.get("tiles"), list) and manifest["tiles"]:
        entry = manifest["tiles"][where[1] % len(manifest["tiles"])]
        if isinstance(entry, dict):
            entry[where[2]] = value
    elif where[0] == "city" and isinstance(manifest.get("city"), dict):
        manifest["city"][where[1]] = value
    elif where[0] == "top":
        manifest[where[1]] = value
    elif where[0] == "nest":
        nested = value
        for _ in range(where[1]):
            nested = [nested]
        manifest["tiles"] = nested


file_damage = st.tuples(
    st.sampled_from(["manifest.json", "city.pickle", "tiles/00000.npz", "tiles/00001.npz"]),
    st.sampled_from(["truncate", "garbage", "flip", "fifo", "link outside", "link to /dev/zero", "remove"]),
    st.integers(0, 4000),
)


def _damage_file(folder: Path, name: str, how: str, at: int):
    path = folder / name
    if path.is_symlink() or not path.is_file():  # damaged already
        return
    data = path.read_bytes()
    if how in ("fifo", "link outside", "link to /dev/zero", "remove"):
        path.unlink()
    if how == "truncate":
        path.write_bytes(data[: at % (len(data) + 1)])
    elif how == "garbage":
        path.write_bytes(data[:at] + os.urandom(64) + data[at + 64 :])
    elif how == "flip" and data:
        spot = at % len(data)
        path.write_bytes(data[:spot] + bytes([data[spot] ^ 0xFF]) + data[spot + 1 :])
    elif how == "fifo":
        os.mkfifo(path)
    elif how == "link outside":
        path.symlink_to(folder.parent / "secret.bin")
    elif how == "link to /dev/zero":
        path.symlink_to("/dev/zero")


@pytest.fixture(scope="module")
def pristine(tmp_path_factory) -> Path:
    """The tagged map's cache in tiles of 64 m (several tiles), made once."""
    folder = tmp_path_factory.mktemp("pristine") / "tiles"
    write_tiles(map_city(load_map(TAGGED)), folder, tile_size=64.0)
    return folder


def check_damaged_cache(pristine: Path, work: Path, edits, files, monkeypatch):
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()
    (work / "secret.bin").write_bytes(SECRET)
    folder = work / "tiles"
    shutil.copytree(pristine, folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    for where, value in edits:
        _apply(manifest, where, value)
    try:
        text = json.dumps(manifest)
    except (ValueError, RecursionError):
        text = "[" * 5000
    (folder / "manifest.json").write_text(text)
    for damage in files:
        _damage_file(folder, *damage)
    real = Path(os.path.realpath(folder))
    read = []
    reader = _tile_cache.read_input_bytes

    def recorded(path, *args, **kwargs):
        read.append(Path(os.path.realpath(path)))
        return reader(path, *args, **kwargs)

    monkeypatch.setattr(_tile_cache, "read_input_bytes", recorded)
    try:
        cache = open_tiles(folder)
        for index in range(len(cache.tiles)):
            read_tile(cache, index)
    except CacheProblem as exc:
        message = str(exc)
        assert "\n" not in message and str(len(SECRET)) not in message and "secret" not in message, message
    assert all(real in path.parents for path in read), read
    assert (work / "secret.bin").read_bytes() == SECRET


@SMALL
@given(edits=manifest_damage(), files=st.lists(file_damage, max_size=2))
def test_damaged_tile_caches_small(pristine, tmp_path_factory, edits, files):
    with pytest.MonkeyPatch.context() as monkeypatch:
        check_damaged_cache(pristine, tmp_path_factory.getbasetemp() / "damaged-small", edits, files, monkeypatch)


# ------------------------------------------------------------------ hostile output markers

marker_names = st.sampled_from(["tileset.json", "tiles/a.glb", "tiles", "../outside.txt", "/etc/passwd", "x/../y"])


@st.composite
def marked_folders(draw):
    """(marker content, the folder's entries: name -> "file" | "link" | "dir")."""
    entries = draw(
        st.dictionaries(
            marker_names.filter(lambda n: not n.startswith(("/", ".."))),
            st.sampled_from(["file", "link", "dir"]),
            max_size=4,
        )
    )
    listed = draw(st.lists(st.one_of(marker_names, hostile_scalar), max_size=6))
    marker = {
        "kind": draw(st.sampled_from(["3dtiles", "tile-cache", None, 7])),
        "format": draw(st.sampled_from([1, 2, "1", None])),
        "files": draw(st.one_of(st.just(listed), hostile_json)),
    }
    content = draw(st.one_of(st.just(json.dumps(marker)), st.text(max_size=20), st.just("[" * 100_000)))
    return content, entries


def check_marked_folder(work: Path, content: str, entries: dict):
    """atomic_folder replaces the folder only when each of its entries is a regular file the
    marker lists (or a folder); otherwise it refuses in one line and the folder is as it was."""
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()
    (work / "outside.txt").write_bytes(SECRET)
    folder = work / "out"
    folder.mkdir()
    (folder / OUTPUT_MARKER).write_text(content)
    for name, kind in entries.items():
        path = folder / name
        if path.exists() or path.is_symlink():
            continue
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except FileExistsError:  # a file of the same name stands above it
            continue
        if kind == "file":
            path.write_text("user")
        elif kind == "link":
            path.symlink_to(work / "outside.txt")
        else:
            path.mkdir()
    before = _entries(folder)
    try:
        marker = json.loads(content)
    except (ValueError, RecursionError):
        marker = None
    try:
        with atomic_folder(folder, "3dtiles") as tmp:
            (tmp / "tileset.json").write_text("{}")
    except UsageError as exc:
        assert "\n" not in str(exc) and str(len(SECRET)) not in str(exc), str(exc)
        assert _entries(folder) == before
    else:
        assert isinstance(marker, dict) and marker.get("kind") == "3dtiles" and marker.get("format") == 1
        listed = {OUTPUT_MARKER, *(name for name in marker["files"] if isinstance(name, str))}
        assert all(kind == "dir" or (kind == "file" and name in listed) for name, kind in before), before
        assert _entries(folder) == [(OUTPUT_MARKER, "file"), ("tileset.json", "file")]
    assert (work / "outside.txt").read_bytes() == SECRET


def _entries(folder: Path) -> list[tuple[str, str]]:
    def kind(path: Path) -> str:
        return "link" if path.is_symlink() else "dir" if path.is_dir() else "file"

    return sorted((p.relative_to(folder).as_posix(), kind(p)) for p in folder.rglob("*"))


@SMALL
@given(folder=marked_folders())
def test_marked_folders_small(tmp_path_factory, folder):
    check_marked_folder(tmp_path_factory.getbasetemp() / "marked-small", *folder)


# ------------------------------------------------------------------ export options

texels = st.one_of(st.floats(), st.just(1e308), st.integers(-5, 5), st.floats(1e-3, 200.0))
lods = st.one_of(st.integers(-3, 30), st.integers(-(10**30), 10**30))
regions = st.one_of(
    st.text(max_size=30),
    st.lists(st.one_of(st.floats(), st.integers(-400, 400)), min_size=3, max_size=5).map(
        lambda v: ",".join(map(str, v))
    ),
    st.just("24.94,60.16,24.95,60.17"),
)
formats = st.one_of(st.sampled_from(FORMATS), st.text(max_size=6))


@pytest.fixture(scope="module")
def tagged_export():
    return map_export_city(TAGGED)


def check_export_options(export, out: Path, fmt, texel, lod, region):
    """check_output, parse_region and crop (what `export` runs before baking): valid, or one line
    naming the option."""
    try:
        check_output(out, fmt, texel, lod)
        crop(export, parse_region(region), region)
    except UsageError as exc:
        message = str(exc)
        assert "\n" not in message and message.startswith("--"), message
    assert not out.exists()


@SMALL
@given(fmt=formats, texel=texels, lod=lods, region=regions)
def test_export_options_small(tagged_export, tmp_path_factory, fmt, texel, lod, region):
    check_export_options(tagged_export, tmp_path_factory.getbasetemp() / "export-out", fmt, texel, lod, region)


# ------------------------------------------------------------------ the long runs (make fuzz)


@pytest.mark.fuzz
def test_damaged_tile_caches_long(pristine, tmp_path_factory):
    work = tmp_path_factory.mktemp("damaged") / "work"

    def check(edits, files):
        with pytest.MonkeyPatch.context() as monkeypatch:
            check_damaged_cache(pristine, work, edits, files, monkeypatch)

    for_a_while(LARGE(given(edits=manifest_damage(), files=st.lists(file_damage, max_size=3))(check)))


@pytest.mark.fuzz
def test_marked_folders_long(tmp_path_factory):
    work = tmp_path_factory.mktemp("marked") / "work"
    for_a_while(LARGE(given(folder=marked_folders())(lambda folder: check_marked_folder(work, *folder))))


@pytest.mark.fuzz
def test_export_options_long(tagged_export, tmp_path_factory):
    out = tmp_path_factory.mktemp("export") / "out"
    for_a_while(
        LARGE(
            given(fmt=formats, texel=texels, lod=lods, region=regions)(
                lambda fmt, texel, lod, region: check_export_options(tagged_export, out, fmt, texel, lod, region)
            )
        )
    )
