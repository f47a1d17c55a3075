# centrobench: every target sets up .venv from the pinned versions on first use.
# The two commands a new user needs: `make bench` (the main job) and `make test` (the tests).

PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: all bench bench-full test test-slow test-all lint format benchmark constraints clean

all: test

# The installer: uv (pinned; the same pins as pip, about 25 s instead of 65 s from a warm cache,
# bytecode compiled as pip does), bootstrapped with pip; pip itself if uv cannot be installed or
# fails (for example where only pip's configured indexes are reachable).
UV_VERSION := 0.13.9
PIP_VERSION := 26.3

$(STAMP): pyproject.toml constraints.txt
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else "centrobench needs Python >= 3.11; set PYTHON=/path/to/python3.11")'
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet "uv==$(UV_VERSION)" \
		&& $(BIN)/uv pip install --quiet --python $(BIN)/python --compile-bytecode \
			-c constraints.txt -e '.[dev]' \
		|| { echo "uv did not install the pins; installing them with pip"; \
			$(BIN)/python -m pip install --quiet --upgrade "pip==$(PIP_VERSION)" \
			&& $(BIN)/python -m pip install --quiet -c constraints.txt -e '.[dev]'; }
	@touch $@

## bench: the main job (bench/specs/main.toml; README "The main job"): every registered
## controller x both simulators on the papers' protocols at fewer levels, then Table 1's speed
## search on a coarse grid, on local processes; results and report in results/latest/
bench: $(STAMP)
	rm -f results/latest/speed.parquet results/latest/speed.md
	$(BIN)/centrobench sweep --spec bench/specs/main.toml --out results/latest --overwrite
	$(BIN)/centrobench speed --controllers all --sims all --increment 0.1 --resolution 0.05 \
		--out results/latest
	$(BIN)/centrobench report results/latest --out results/latest

## bench-full: the complete protocols for publication (bench/specs/main_full.toml, then Table 1's
## search on the issue's grid, 0.05 / 0.01 m/s, for Table 1's rows, the direct_centroidal
## ablations, and every other controller): hours on 2 cores; run it again to resume the sweep
## (the speed search runs again whole); results and report in results/full/
TABLE_1_ROWS := all,direct_centroidal/open_loop,direct_centroidal/straight_leg,$\
	direct_centroidal/closed_loop,direct_centroidal/leaky,direct_centroidal/extended,$\
	direct_centroidal/inertia,direct_centroidal/step_timing,direct_centroidal/bent_no_inertia,$\
	direct_centroidal/bent_no_inertia_feedforward
bench-full: $(STAMP)
	$(BIN)/centrobench sweep --spec bench/specs/main_full.toml --out results/full --resume
	$(BIN)/centrobench speed --controllers $(TABLE_1_ROWS) --sims all --out results/full
	$(BIN)/centrobench report results/full --out results/full

## test: the test suite without the long simulations (what CI runs)
test: $(STAMP)
	$(BIN)/python -m pytest

## test-slow: only the long simulations (exit code 5 = none collected, not a failure)
test-slow: $(STAMP)
	$(BIN)/python -m pytest -m slow; rc=$$?; [ $$rc -eq 0 ] || [ $$rc -eq 5 ]

## test-all: everything but the timing benchmarks
test-all: $(STAMP)
	$(BIN)/python -m pytest -m 'not benchmark'

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

format: $(STAMP)
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

## benchmark: pytest-benchmark timing runs (exit code 5 = none collected yet, not a failure)
benchmark: $(STAMP)
	$(BIN)/python -m pytest -m benchmark --benchmark-enable --benchmark-only \
		--benchmark-json=build/benchmark.json; rc=$$?; [ $$rc -eq 0 ] || [ $$rc -eq 5 ]

## constraints: re-resolve every pin from pyproject.toml (then re-run the agreement tests)
constraints:
	rm -rf build/constraints-venv
	$(PYTHON) -m venv build/constraints-venv
	build/constraints-venv/bin/python -m pip install --quiet --upgrade pip
	build/constraints-venv/bin/python -m pip install --quiet -e '.[dev,ray]'
	build/constraints-venv/bin/python -m pip freeze --exclude-editable > build/constraints.new
	@echo "review build/constraints.new and merge it into constraints.txt (keep the header)"

clean:
	rm -rf $(VENV) build results .pytest_cache .ruff_cache
