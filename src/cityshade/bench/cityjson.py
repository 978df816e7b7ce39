"""`cityshade bench cityjson`: CityJSON drawn as given, buildings per second.

A 3D BAG-sized tile: the real 3D BAG subset of cityshade's test data (tests/data/cityjson/
multi_lod.city.json: 10 buildings, LoD 1.2, 1.3 and 2.2) copied side by side on a grid until it
holds TILE_BUILDINGS buildings (--quick: QUICK_BUILDINGS), written as a CityJSON document and as
CityJSONSeq (a feature per building). Timed: `load_map` + `map_city` + `scene.batch` (reading,
guessing, the masses with their faces as given and the city objects' layer, the meshes), in process
after imports, the median of REPEATS runs. The real LoD2 subsets of Zurich (BuildingParts) and
Rotterdam are timed the same way as they are. Target: the tile in under TARGET_SECONDS.
"""

from __future__ import annotations

import json
import statistics
import tempfile
import time
from pathlib import Path

from ..errors import CityshadeError
from ..maps import load_map, map_city
from ..scene import batch
from ._harness import BenchResult

DATA = Path(__file__).resolve().parents[3] / "tests" / "data" / "cityjson"
TILE_SOURCE = DATA / "multi_lod.city.json"
REAL = {
    "Zurich LoD2 (BuildingParts)": DATA / "zurich_lod2.city.json",
    "Rotterdam LoD2": DATA / "rotterdam_lod2.city.json",
}
TILE_BUILDINGS, QUICK_BUILDINGS = 5000, 500
REPEATS = {True: 1, False: 3}
TARGET_SECONDS = 5.0
GAP = 20.0  # metres between copies


def _flat(boundaries):
    for item in boundaries:
        if isinstance(item, list):
            yield from _flat(item)
        else:
            yield item


def _shifted(boundaries, offset: int):
    return [_shifted(item, offset) if isinstance(item, list) else item + offset for item in boundaries]


def tiled(source: Path, buildings: int) -> dict:
    """The document copied on a grid until it holds `buildings` Building objects (at least)."""
    document = json.loads(source.read_text())
    objects, vertices = document["CityObjects"], document["vertices"]
    scale = document["transform"]["scale"]
    xs, ys = [v[0] for v in vertices], [v[1] for v in vertices]
    step_x = (max(xs) - min(xs)) + GAP / scale[0]
    step_y = (max(ys) - min(ys)) + GAP / scale[1]
    per_copy = sum(o["type"] == "Building" for o in objects.values())
    copies = -(-buildings // per_copy)
    side = int(copies**0.5) + 1
    out_objects, out_vertices = {}, []
    for k in range(copies):
        dx, dy = round((k % side) * step_x), round((k // side) * step_y)
        offset = len(out_vertices)
        out_vertices += [[x + dx, y + dy, z] for x, y, z in vertices]
        for name, obj in objects.items():
            copy = dict(obj)
            copy["geometry"] = [{**g, "boundaries": _shifted(g["boundaries"], offset)} for g in obj.get("geometry", [])]
            for key in ("parents", "children"):
                if key in obj:
                    copy[key] = [f"{other}-{k}" for other in obj[key]]
            out_objects[f"{name}-{k}"] = copy
    return {**document, "CityObjects": out_objects, "vertices": out_vertices}


def sequence_lines(document: dict) -> list[str]:
    """The document as CityJSONSeq: its header, then a feature per building with its parts."""
    header = {k: v for k, v in document.items() if k not in ("CityObjects", "vertices")}
    lines = [json.dumps({**header, "CityObjects": {}, "vertices": []})]
    objects, vertices = document["CityObjects"], document["vertices"]
    for name, obj in objects.items():
        if obj.get("parents"):
            continue
        members = {name: obj, **{c: objects[c] for c in obj.get("children", []) if c in objects}}
        used = sorted({i for o in members.values() for g in o.get("geometry", []) for i in _flat(g["boundaries"])})
        index = {old: new for new, old in enumerate(used)}
        remapped = {
            n: {
                **o,
                "geometry": [{**g, "boundaries": _remapped(g["boundaries"], index)} for g in o.get("geometry", [])],
            }
            for n, o in members.items()
        }
        feature = {
            "type": "CityJSONFeature",
            "id": name,
            "CityObjects": remapped,
            "vertices": [vertices[i] for i in used],
        }
        lines.append(json.dumps(feature))
    return lines


def _remapped(boundaries, index: dict):
    return [_remapped(item, index) if isinstance(item, list) else index[item] for item in boundaries]


def _timed(path: Path, repeats: int) -> tuple[float, int, int]:
    """(median seconds of load_map + map_city + batch, buildings drawn, masses)."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        data = load_map(path)
        city = map_city(data)
        batch(city.masses)
        times.append(time.perf_counter() - start)
    return statistics.median(times), data.drawn_types.get("Building", 0), len(city.masses)


def _measured_row(rows: list, label: str, path: Path, repeats: int) -> float:
    """Times loading `path`, adds its table row to `rows`, and returns the seconds."""
    seconds, buildings, masses = _timed(path, repeats)
    size = round(path.stat().st_size / 1e6, 2)
    rows.append([label, buildings, masses, size, round(seconds, 2), round(buildings / seconds, 1)])
    return seconds


def run(quick: bool, out_dir: Path) -> BenchResult:
    if not TILE_SOURCE.is_file():
        raise CityshadeError(f"{TILE_SOURCE} is missing: the benchmark runs in cityshade's source tree", exit_code=2)
    repeats, wanted = REPEATS[quick], QUICK_BUILDINGS if quick else TILE_BUILDINGS
    result = BenchResult("cityjson", "CPU (no GPU work)")
    result.methods = {
        "load": {"what": "load_map + map_city + scene.batch, in process after imports", "repeats": repeats},
    }
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        document = tiled(TILE_SOURCE, wanted)
        tile = Path(folder) / "tile.city.json"
        tile.write_text(json.dumps(document, separators=(",", ":")))
        sequence = Path(folder) / "tile.city.jsonl"
        sequence.write_text("\n".join(sequence_lines(document)) + "\n")
        for label, path in (("3D BAG tile, document", tile), ("3D BAG tile, CityJSONSeq", sequence)):
            seconds = _measured_row(rows, label, path, repeats)
            result.ratios[f"{'seq' if path is sequence else 'document'}_tile_seconds"] = seconds
    for label, path in REAL.items():
        _measured_row(rows, label, path, repeats)
    result.add_table(
        f"Load and mesh ({wanted} tiled buildings of {TILE_SOURCE.name})",
        ["file", "buildings", "masses", "MB", "seconds", "buildings per second"],
        rows,
    )
    result.targets = {"document_tile_seconds": f"< {TARGET_SECONDS:g} (at {TILE_BUILDINGS} buildings)"}
    result.notes.append("buildings: CityJSON Building objects drawn; masses: the meshed buildings and parts")
    return result
