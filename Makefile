# cityshade: `make demo` renders the default city, `make test` runs the suite (`make test-slow`: the
# command-line render checks that take minutes), `make lint` checks style.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
EGL_PKGS := libegl1 libegl-mesa0 libgl1-mesa-dri

BENCHES := interior facades relief trees
# `ruff format --check` covers these paths; the rest of the tree joins them as it is next edited
# (reformatting every file at once would collide with concurrent work on it).
FORMATTED := src/cityshade/gl src/cityshade/arguments.py src/cityshade/render/_facades.py src/cityshade/shader_constants.py \
             tests/test_frame.py tests/test_boundaries.py tests/test_constants.py

.PHONY: setup demo lint test test-slow fuzz bench bench-quick clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	@bash scripts/ensure-egl.sh $(EGL_PKGS)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[test]'
	@touch $(STAMP)

demo: setup
	$(BIN)/cityshade render --out out/city.png

lint: setup
	$(BIN)/ruff check src tests examples scripts
	$(BIN)/ruff format --check $(FORMATTED)

test: setup
	$(BIN)/python -m pytest -n 2 -q -m "not slow and not fuzz"

test-slow: setup
	$(BIN)/python -m pytest -n 2 -q -m slow

# The fuzzers with a large budget: CITYSHADE_FUZZ_SECONDS per fuzzer (default 60; docs/robustness.md).
fuzz: setup
	$(BIN)/python -m pytest -n 2 -q -m fuzz tests/test_fuzz.py

bench: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --json bench-results/$$b.json || exit 1; done

bench-quick: setup
	for b in $(BENCHES); do $(BIN)/cityshade bench $$b --quick --json bench-results/$$b-quick.json || exit 1; done

clean:
	rm -rf $(VENV) out bench-results
