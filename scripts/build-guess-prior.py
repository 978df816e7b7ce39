"""Rebuild src/cityshade/maps/guess_prior.json.gz, the guessing model's prior, from tagged maps.

    python scripts/build-guess-prior.py [--out PATH]

Trains on the tagged buildings of data/Helsinki.osm.pbf (`make data`) and of the extracts in
scripts/prior-maps/ (Andorra, Monaco; see the NOTICE there). All are © OpenStreetMap contributors,
ODbL 1.0. The same maps give the same bytes (LightGBM on one thread with fixed seeds, gzip without a
time stamp); docs/guesses.md says what the file holds.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cityshade._files import write_bytes
from cityshade.maps import PRIOR_FILE, load_map, prior_bytes, train_prior

ROOT = Path(__file__).resolve().parents[1]
MAPS = {
    "Helsinki": ROOT / "data" / "Helsinki.osm.pbf",
    "Andorra": ROOT / "scripts" / "prior-maps" / "Andorra.osm.pbf",
    "Monaco": ROOT / "scripts" / "prior-maps" / "Monaco.osm.pbf",
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=PRIOR_FILE, help="where to write the prior")
    args = parser.parse_args()
    missing = [str(path) for path in MAPS.values() if not path.exists()]
    if missing:
        print(f"{missing[0]}: missing; run `make data` (Helsinki) or restore scripts/prior-maps/", file=sys.stderr)
        return 2
    document = train_prior({name: load_map(path) for name, path in MAPS.items()})
    data = prior_bytes(document)
    write_bytes(args.out, data)
    for name, city in document["cities"].items():
        print(f"{name}: {city['rows_levels']} level rows, {city['rows_roof']} roof rows, bounds {city['bbox']}")
    print(f"wrote {args.out} ({len(data):,} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
