# Two set-up-free entry points: `make reproduce` (the main job) and `make test` (the suite but
# its `slow` tests; `make test-slow` runs those alone, as CI does after `make test`; `make test-all`
# runs everything in one go).
# Each creates .venv on first use, installs the project with what it needs and compiles every
# kernel (`chassistune warmup`, cached on disk).
PY ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-stamp

.PHONY: reproduce demo test test-all test-slow lint bench clean-venv

$(STAMP): pyproject.toml
	@command -v $(PY) >/dev/null 2>&1 || { echo "make: $(PY) not found; set PY=python3.X (>= 3.11)" >&2; exit 2; }
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	$(BIN)/python -m pip install -q --no-deps mealpy==3.0.3 opfunu==1.0.4
	$(BIN)/chassistune warmup
	touch $(STAMP)

reproduce: $(STAMP)
	$(BIN)/chassistune reproduce all --quick --out reproduce-output

demo: $(STAMP)
	$(BIN)/chassistune demo --out demo-output

# warmup first: after a change of the sources it compiles every kernel once, in two processes,
# instead of in each test worker; with the cache warm it only loads them.
test: lint
	$(BIN)/chassistune warmup
	$(BIN)/python -m pytest -m "not slow"

test-all: lint
	$(BIN)/chassistune warmup
	$(BIN)/python -m pytest

test-slow: $(STAMP)
	$(BIN)/chassistune warmup
	$(BIN)/python -m pytest -m slow

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy

bench: $(STAMP)
	$(BIN)/chassistune bench

clean-venv:
	rm -rf $(VENV)
