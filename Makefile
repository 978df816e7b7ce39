# cityshade: `make demo` renders the default city, `make test` runs the suite (`make test-slow`: the
# command-line render checks that take minutes).
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
EGL_PKGS := libegl1 libegl-mesa0 libgl1-mesa-dri

BENCHES := interior facades relief trees

.PHONY: setup demo test test-slow fuzz bench bench-quick clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	@bash scripts/ensure-egl.sh $(EGL_PKGS)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[test]'
	@touch $(STAMP)

demo: setup
	$(BIN)/cityshade render --out out/city.png

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
