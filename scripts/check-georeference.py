"""A tileset's buildings against their own OpenStreetMap nodes: every node of every building way
read from the extract (pyosmium) and taken to EPSG:4978 by pyproj, against the nearest exported
vertex (cityshade.export.testing.tileset_points: the tile transforms, glTF's y-up turned z-up, the
node transforms), both brought to the ellipsoid (height 0) so that the distance is horizontal.

    python scripts/check-georeference.py out/export/helsinki-tiles data/Helsinki.osm.pbf [--max 0.5]

Prints the median, 99th percentile and largest distance in metres over the ways drawn as
themselves (half their nodes or more within --max: an outline replaced by its building:parts, or a
way the reader skipped, is counted apart), and how many of their nodes lie farther than --max: nodes
the reader leaves out of a repaired outline have no vertex of their own. Exits 1 when the median is
over --max / 10 or more than 1% of the nodes lie farther than --max (a misplaced tileset fails both)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import osmium
import pyproj
from scipy.spatial import cKDTree

from cityshade.export.testing import tileset_points


def building_nodes(path: Path) -> list[np.ndarray]:
    """(lon, lat) of each building or building:part way's nodes."""
    ways = []
    for way in (
        osmium.FileProcessor(str(path))
        .with_locations()
        .with_filter(osmium.filter.KeyFilter("building", "building:part"))
    ):
        if way.is_way():
            ways.append(np.array([(n.lon, n.lat) for n in way.nodes if n.location.valid()]))
    return [w for w in ways if len(w)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tileset", type=Path)
    parser.add_argument("osm", type=Path)
    parser.add_argument("--max", type=float, default=0.5, help="metres allowed (default 0.5)")
    args = parser.parse_args()
    to_geodetic = pyproj.Transformer.from_crs("EPSG:4978", "EPSG:4979", always_xy=True)
    to_ecef = pyproj.Transformer.from_crs("EPSG:4979", "EPSG:4978", always_xy=True)
    exported = tileset_points(args.tileset)
    lon, lat, _ = to_geodetic.transform(exported[:, 0], exported[:, 1], exported[:, 2])
    tree = cKDTree(np.column_stack(to_ecef.transform(lon, lat, np.zeros(len(lon)))))
    drawn, skipped = [], 0
    for way in building_nodes(args.osm):
        distance, _ = tree.query(np.column_stack(to_ecef.transform(way[:, 0], way[:, 1], np.zeros(len(way)))))
        if np.median(distance) > args.max:
            skipped += 1
        else:
            drawn.append(distance)
    if not drawn:
        print(json.dumps({"ways": 0, "ways_not_drawn": skipped, "error": f"no way within {args.max} m of the tileset"}))
        return 1
    d = np.concatenate(drawn)
    result = {
        "ways": len(drawn),
        "ways_not_drawn": skipped,
        "nodes": len(d),
        "median_m": round(float(np.median(d)), 4),
        "p99_m": round(float(np.percentile(d, 99)), 4),
        "max_m": round(float(d.max()), 4),
        "nodes_over_max": int((d > args.max).sum()),
    }
    print(json.dumps(result))
    return 0 if np.median(d) <= args.max / 10 and result["nodes_over_max"] <= 0.01 * len(d) else 1


if __name__ == "__main__":
    sys.exit(main())
