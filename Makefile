# pampipe: every target creates the virtual environment it needs; nothing else must be installed first.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
LOCK   := requirements.lock
LATEST := .venv-latest
DOCS_VENV := .docs-venv

.PHONY: demo test test-slow test-latest lock lint bench bench-all fuzz mutate docs clean

# pip shows errors only: a build log would hide what the target is for
PIP    := -m pip install -qq --disable-pip-version-check

$(BIN)/python:
	@echo "creating $(VENV) (once)"
	@$(PYTHON) -m venv $(VENV)
	@$(BIN)/python $(PIP) --upgrade pip

$(STAMP): pyproject.toml $(LOCK) | $(BIN)/python
	@echo "installing pampipe and the tested versions of its dependencies ($(LOCK)) into $(VENV)"
	@$(BIN)/python $(PIP) --constraint $(LOCK) -e ".[test]"
	@$(BIN)/python -m compileall -q pampipe  # bytecode as a wheel install has it, even under PYTHONDONTWRITEBYTECODE
	@touch $(STAMP)

demo: $(STAMP)  ## plan the bundled demo mission
	$(BIN)/pampipe plan problems/missions/vertical-climb-3in.yaml

# test workers (pytest-xdist): 2, or fewer on a 1-core machine; TEST_WORKERS=0 runs in one process
TEST_WORKERS ?= $(shell $(PYTHON) -c "import os; print(min(2, len(os.sched_getaffinity(0))))" 2>/dev/null || echo 2)

test: $(STAMP)  ## the default test run (slow tests excluded), on $(TEST_WORKERS) workers
	$(BIN)/python -m pytest -m "not slow" -q -n $(TEST_WORKERS)

test-slow: $(STAMP)  ## everything, slow tests included
	$(BIN)/python -m pytest -q

test-latest:  ## the suite against the newest release of every dependency, in its own venv (finds drift first)
	$(PYTHON) -m venv $(LATEST)
	$(LATEST)/bin/python $(PIP) --upgrade pip
	$(LATEST)/bin/python $(PIP) --upgrade --upgrade-strategy eager -e ".[test]"
	$(LATEST)/bin/python -m pip list --format=freeze | grep -v -i '^pampipe' > $(LATEST)/tested-versions.txt
	$(LATEST)/bin/python -m pytest -m "not slow" -q -p no:cacheprovider

lock: | $(BIN)/python  ## refresh requirements.lock, the tested versions that every other target installs
	$(BIN)/python $(PIP) uv
	$(BIN)/python -m uv pip compile --quiet pyproject.toml --extra test --extra dask \
		--python-version 3.10 --universal -o $(LOCK)

fuzz: $(STAMP)  ## long property-based fuzzing profile: 10^4 mutated problem files through the CLI
	PAMPIPE_FUZZ_EXAMPLES=$${PAMPIPE_FUZZ_EXAMPLES:-10000} PAMPIPE_FUZZ_RANDOM=1 \
		$(BIN)/python -m pytest tests/commands/test_fuzz.py -q -p no:cacheprovider

docs:  ## the docs with the API reference from the docstrings (out/site); own venv, not the lock; a warning fails it
	@test -x $(DOCS_VENV)/bin/mkdocs || { $(PYTHON) -m venv $(DOCS_VENV) && $(DOCS_VENV)/bin/python $(PIP) \
		"mkdocs==1.6.1" "mkdocstrings==1.0.8" "mkdocstrings-python==2.0.11" "mkdocs-material==9.8.2"; }
	NO_MKDOCS_2_WARNING=1 $(DOCS_VENV)/bin/mkdocs build --strict

mutate: $(STAMP)  ## mutation testing of the safety modules (scripts/mutate.py; MUTATE_ARGS="--sample 40")
	$(BIN)/python scripts/mutate.py $(MUTATE_ARGS)

lint: $(STAMP)
	$(BIN)/ruff check pampipe tests benchmarks

# the scripts docs/performance.md quotes, each with >= 5 alternated rounds (median, spread, load); BENCH_BASELINE=TREE
# (a checkout of main, say) also times that tree's big-mission plan in the same rounds
BENCH_BASELINE ?=
bench: $(STAMP)  ## the benchmarks docs/performance.md quotes (median and spread of >= 5 alternated runs, the load)
	@echo "== benchmarks/bench_startup.py --repeat 7"; $(BIN)/python benchmarks/bench_startup.py --repeat 7
	@echo "== benchmarks/bench_big_mission.py --sections 100000 --repeat 5"; $(BIN)/python \
		benchmarks/bench_big_mission.py --sections 100000 --repeat 5 $(if $(BENCH_BASELINE),--baseline $(BENCH_BASELINE))
	@echo "== benchmarks/bench_identify.py --scales 10 100 --repeat 5"; $(BIN)/python benchmarks/bench_identify.py \
		--scales 10 100 --repeat 5
	@echo "== benchmarks/bench_identify_floor.py --scales 10 100 --repeat 5"; $(BIN)/python \
		benchmarks/bench_identify_floor.py --scales 10 100 --repeat 5
	@echo "== benchmarks/bench_identify_floor.py --scales 1000 --repeat 3 --no-peer"; $(BIN)/python \
		benchmarks/bench_identify_floor.py --scales 1000 --repeat 3 --no-peer
	@echo "== benchmarks/bench_confidence.py --sections '' --distinct 100000 --repeat 5"; $(BIN)/python \
		benchmarks/bench_confidence.py --sections '' --distinct 100000 --repeat 5

bench-all: $(STAMP)  ## every script in benchmarks/ with its defaults (some print no spread: their figures are not quoted)
	for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) $(LATEST) $(DOCS_VENV) build *.egg-info .pytest_cache .ruff_cache .hypothesis
