"""Large synthetic extracts for load benchmarks: a real extract's buildings repeated on a grid.

`tiled_extract` copies every closed building way (outlines and parts, with their tags) of a source
.osm.pbf side by side, each copy shifted by whole tiles of longitude/latitude and given fresh node
and way ids, until the file holds at least the requested number of buildings. `measure_load` times
`load_map` on a file in a fresh Python process and reports its peak memory.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import osmium

from ..errors import CityshadeError
from .features import is_building

TILE_GAP = 0.0005  # degrees between copies, so no two tiles' buildings touch


def _building_ways(source: Path):
    """(ways as (tags, node refs), node locations by id, bounds) of the closed building ways of `source`."""
    ways, wanted = [], set()
    for way in osmium.FileProcessor(str(source), osmium.osm.WAY):
        refs = [node.ref for node in way.nodes]
        if is_building(way.tags) and len(refs) >= 4 and refs[0] == refs[-1]:
            ways.append((dict(way.tags), refs))
            wanted.update(refs)
    nodes = {}
    for node in osmium.FileProcessor(str(source), osmium.osm.NODE):
        if node.id in wanted and node.location.valid():
            nodes[node.id] = (node.location.lon, node.location.lat)
    ways = [(tags, refs) for tags, refs in ways if all(ref in nodes for ref in refs)]
    if not ways:
        raise CityshadeError(f"{source}: no closed building way to tile", exit_code=2)
    lons = [lon for lon, _ in nodes.values()]
    lats = [lat for _, lat in nodes.values()]
    return ways, nodes, (min(lons), min(lats), max(lons), max(lats))


def tiled_extract(source: Path | str, target: Path | str, buildings: int = 100_000) -> dict:
    """Write `target` (.osm.pbf) with at least `buildings` building ways tiled from `source`.

    Returns {"buildings", "tiles", "nodes"} of the written file. An existing `target` is replaced."""
    source, target = Path(source), Path(target)
    ways, nodes, (lon0, lat0, lon1, lat1) = _building_ways(source)
    tiles = math.ceil(buildings / len(ways))
    columns = math.ceil(math.sqrt(tiles))
    step_lon, step_lat = lon1 - lon0 + TILE_GAP, lat1 - lat0 + TILE_GAP
    node_ids = {ref: i + 1 for i, ref in enumerate(sorted(nodes))}
    stride = len(node_ids)
    target.unlink(missing_ok=True)
    writer = osmium.SimpleWriter(str(target))
    try:
        for tile in range(tiles):
            dlon, dlat = (tile % columns) * step_lon, (tile // columns) * step_lat
            for ref, new in node_ids.items():
                lon, lat = nodes[ref]
                writer.add_node(osmium.osm.mutable.Node(id=tile * stride + new, location=(lon + dlon, lat + dlat)))
        for tile in range(tiles):
            for i, (tags, refs) in enumerate(ways):
                writer.add_way(
                    osmium.osm.mutable.Way(
                        id=tile * len(ways) + i + 1, tags=tags, nodes=[tile * stride + node_ids[ref] for ref in refs]
                    )
                )
    finally:
        writer.close()
    return {"buildings": tiles * len(ways), "tiles": tiles, "nodes": tiles * stride}


_MEASURE = """
import json, resource, sys, time
from cityshade.maps import load_map
start, cpu = time.perf_counter(), time.process_time()
data = load_map(sys.argv[1])
seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps({"seconds": seconds, "cpu_seconds": cpu_seconds, "peak_bytes": peak, "buildings": len(data.buildings),
                  "roads": len(data.roads), "trees": len(data.trees)}))
"""


def measure_load(path: Path | str) -> dict:
    """`load_map(path)` in a fresh interpreter: wall and CPU seconds (they differ on a busy machine),
    peak resident bytes (whole process, imports included), buildings, buildings per second and peak
    bytes per building."""
    done = subprocess.run([sys.executable, "-c", _MEASURE, str(path)], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        raise CityshadeError(f"{path}: loading failed: {lines[-1] if lines else 'no output'}")
    result = json.loads(done.stdout.strip().splitlines()[-1])
    result["buildings_per_second"] = result["buildings"] / max(result["seconds"], 1e-9)
    result["bytes_per_building"] = result["peak_bytes"] / max(result["buildings"], 1)
    return result
