"""`load_map(path)`: pick the reader by the file's first bytes (then its extension) and check the result.

Only regular files are read (a directory, a FIFO or /dev/zero is refused before any byte is read),
JSON files up to MAX_JSON_BYTES. A file that yields no building, road, area, tree or lamp raises
a UsageError (exit code 2) that names the file and the commonest reason features were skipped.
"""

from __future__ import annotations

from pathlib import Path

from .._files import checked_input_size
from ..errors import UsageError
from ..terrain import read_terrain
from ._model import MapData
from ._osm import osm_format, read_osm

MAX_JSON_BYTES = 1 << 30  # 1 GiB of JSON is millions of buildings; more is a mistake or an attack
# Reading CityJSON peaks at about 24 times the file's size (measured with getrusage and tracemalloc
# on generated LoD2 blocks: nested lists of Python ints and floats, then numpy and shapely copies),
# so 256 MiB keeps the peak near 6 GiB. Larger files are a region: split them into tiles.
MAX_CITYJSON_BYTES = 256 << 20
SNIFF_BYTES = 4096
FORMATS = ".osm.pbf, .pbf, .osm (or .osm.gz, .osm.bz2), .geojson, .json, .city.json, .city.jsonl"


def _format(path: Path) -> str:
    """'osm', 'cityjson' or 'geojson', from the content where it tells, else the extension."""
    if osm_format(path) is not None:
        return "osm"
    with open(path, "rb") as stream:
        head = stream.read(SNIFF_BYTES)
    text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    name = path.name.lower()
    if text.startswith(b"{"):
        if b'"CityJSONFeature"' in head or name.endswith(".jsonl"):
            return "cityjsonseq"
        if b'"CityJSON"' in head or b'"CityObjects"' in head or name.endswith(".city.json"):
            return "cityjson"
        return "geojson"
    for ending, kind in (
        (".city.jsonl", "cityjsonseq"),
        (".pbf", "osm"),
        (".osm", "osm"),
        (".city.json", "cityjson"),
        (".geojson", "geojson"),
        (".json", "geojson"),
    ):
        if name.endswith(ending):
            return kind
    raise UsageError(f"{path}: not a map file this reader knows; use {FORMATS}")


def read_json_text(path: Path, size: int, kind: str = "geojson") -> str:
    limit = MAX_CITYJSON_BYTES if kind == "cityjson" else MAX_JSON_BYTES
    if size > limit:
        raise UsageError(
            f"{path}: {size:,} bytes of {'CityJSON' if kind == 'cityjson' else 'JSON'} is above the "
            f"{limit:,}-byte limit; split the file into tiles or convert it to .osm.pbf"
        )
    try:
        return path.read_bytes().decode("utf-8-sig")
    except OSError as exc:
        raise UsageError(f"{path}: cannot read the map ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        raise UsageError(f"{path}: byte {exc.start}: not UTF-8 text") from None


def _json_lines(path: Path):
    """A CityJSONSeq file's lines, one at a time (a line over MAX_CITYJSON_BYTES is refused)."""
    try:
        with open(path, encoding="utf-8-sig") as stream:
            while line := stream.readline(MAX_CITYJSON_BYTES + 1):
                if len(line) > MAX_CITYJSON_BYTES:
                    raise UsageError(
                        f"{path}: a line of over {MAX_CITYJSON_BYTES:,} characters is no CityJSONSeq feature; "
                        "write one building with its parts per line"
                    )
                yield line
    except OSError as exc:
        raise UsageError(f"{path}: cannot read the map ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        raise UsageError(f"{path}: byte {exc.start} of a line: not UTF-8 text") from None


def load_map(path: Path | str, lod: str | None = None, terrain: Path | str | None = None) -> MapData:
    """The map at `path` (OpenStreetMap .osm.pbf/.osm, GeoJSON, CityJSON, CityJSONSeq) in local metres.
    `lod`: the CityJSON level of detail to draw ("2", "1.2"; None: each object's highest). `terrain`:
    a DEM file read under the map (terrain.read_terrain; the DEM's repairs counted in the report)."""
    path = Path(path)
    size = checked_input_size(path, "map", FORMATS)
    try:
        kind = _format(path)
    except OSError as exc:  # e.g. no permission to read it
        raise UsageError(f"{path}: cannot read the map ({exc.strerror or exc})") from None
    if kind == "osm":
        data = read_osm(path)
    elif kind == "cityjson":
        from ._cityjson import read_cityjson

        data = read_cityjson(path, read_json_text(path, size, kind), lod)
    elif kind == "cityjsonseq":
        from ._cityjson import read_cityjson_seq

        data = read_cityjson_seq(path, _json_lines(path), lod)
    else:
        from ._geojson import read_geojson

        data = read_geojson(path, read_json_text(path, size))
    if not (data.buildings or data.roads or data.areas or data.trees or data.lamps or data.railways):
        raise UsageError(f"{path}: nothing usable in the map{_commonest_skip(data)}")
    if terrain is not None:
        data.terrain = read_terrain(terrain, data.crs, data.origin, data.bounds())
        for why, count in data.terrain.counts.items() if data.terrain is not None else ():
            data.report.repaired[("terrain samples", why)] += count
    return data


def _commonest_skip(data: MapData) -> str:
    if not data.report.skipped:
        return " (no buildings, roads, areas, trees or street lamps)"
    (what, why), count = data.report.skipped.most_common(1)[0]
    example = data.report.examples.get((what, why))
    return f": {count} {what} skipped, {why}" + (f" (e.g. {example})" if example else "")
