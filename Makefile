# pampipe: every target creates the virtual environment it needs; nothing else must be installed first.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test test-slow lint bench fuzz clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[test]"
	$(BIN)/python -m compileall -q pampipe  # bytecode as a wheel install has it, even under PYTHONDONTWRITEBYTECODE
	touch $(STAMP)

demo: $(STAMP)  ## plan the bundled demo mission
	$(BIN)/pampipe plan problems/missions/vertical-climb-3in.yaml

test: $(STAMP)  ## the default test run (slow tests excluded)
	$(BIN)/python -m pytest -m "not slow" -q

test-slow: $(STAMP)  ## everything, slow tests included
	$(BIN)/python -m pytest -q

fuzz: $(STAMP)  ## long property-based fuzzing profile: 10^4 mutated problem files through the CLI
	PAMPIPE_FUZZ_EXAMPLES=$${PAMPIPE_FUZZ_EXAMPLES:-10000} PAMPIPE_FUZZ_RANDOM=1 \
		$(BIN)/python -m pytest tests/test_fuzz.py -q -p no:cacheprovider

lint: $(STAMP)
	$(BIN)/ruff check pampipe tests benchmarks

bench: $(STAMP)  ## all benchmarks (prints timings and ratios)
	for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .ruff_cache .hypothesis
