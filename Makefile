# The two commands of the README, and a few helpers. Every target sets
# itself up first (scripts/setup.sh is idempotent and fast when done).
PY := .venv/bin/python
PROFILE ?= paper

.PHONY: setup test test-fast lint notebooks book book-quick book-plan records demo bench

setup:
	@bash scripts/setup.sh

# Tests run on every core (pytest-xdist, at most 4 workers); a test file stays
# on one worker, so the quick book (one module fixture) is built once. Files
# are queued in the order tests/conftest.py sorts them (the book first), not
# by their number of tests.
PYTEST := $(PY) -m pytest -q -n auto --maxprocesses 4 --dist loadfile --no-loadscope-reorder

## Pass every test (CI runs this; the slow ones too: 60 s physics runs, the book build, PostgreSQL, SIGKILL).
test: setup
	$(PYTEST)

## The developer's loop: every test not marked slow (about 6-9 min on 2 cores).
test-fast: setup
	$(PYTEST) -m "not slow"

## Lint and format check (what CI runs before the tests).
lint: setup
	.venv/bin/ruff check .
	.venv/bin/ruff format --check .

## Write notebooks/*.ipynb (no outputs) from their sources notebooks/src/*.py.
notebooks: setup
	.venv/bin/jupytext --sync notebooks/src/*.py

## The executable book, full paper profile (results cached under results/): every
## planned run first, in one pool on every core, longest first; then the notebooks.
book: setup
	.venv/bin/mat-hopper plan --profile $(PROFILE) --run
	MAT_HOPPER_PROFILE=$(PROFILE) .venv/bin/jupyter-book build . -W -n --keep-going
	@echo "open _build/html/index.html"

## book/records (what the quick book and the Findings page show of the paper
## profile) rebuilt from the paper book just built: run after `make book`.
records: setup
	.venv/bin/mat-hopper records --profile paper --force

## The same book on the quick profile (short runs; what CI builds).
book-quick:
	$(MAKE) book PROFILE=quick

## The book's runs per chapter, counted before any run (shared, cached, core-hours).
book-plan: setup
	.venv/bin/mat-hopper plan --profile $(PROFILE)

## The paper's forward-hopping comparison of the five mono-materials.
demo: setup
	@mkdir -p results/demo
	@for d in MD PVC Al Ti SS; do \
	  .venv/bin/mat-hopper simulate --design $$d --behaviour forward --csv results/demo/$$d-forward.csv --force || exit 1; \
	done

## Speed benchmarks (ratios measured side by side in one run).
bench: setup
	$(PY) benchmarks/rollout.py
	$(PY) benchmarks/optimize.py
	$(PY) benchmarks/reproduce.py
