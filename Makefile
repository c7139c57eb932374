# The two commands of the README, and a few helpers. Every target sets
# itself up first (scripts/setup.sh is idempotent and fast when done).
PY := .venv/bin/python
PROFILE ?= paper

.PHONY: setup test book book-quick demo bench

setup:
	@bash scripts/setup.sh

## Pass the tests (CI runs this).
test: setup
	$(PY) -m pytest -q

## The executable book, full paper profile (results cached under results/).
book: setup
	MAT_HOPPER_PROFILE=$(PROFILE) .venv/bin/jupyter-book build . -W -n --keep-going
	@echo "open _build/html/index.html"

## The same book on the quick profile (short runs; what CI builds).
book-quick:
	$(MAKE) book PROFILE=quick

## The paper's forward-hopping comparison of the five mono-materials.
demo: setup
	@mkdir -p results/demo
	@for d in MD PVC Al Ti SS; do \
	  .venv/bin/mat-hopper simulate --design $$d --behaviour forward --csv results/demo/$$d-forward.csv || exit 1; \
	done

## Speed benchmarks (ratios measured side by side in one run).
bench: setup
	$(PY) benchmarks/rollout.py
	$(PY) benchmarks/optimize.py
	$(PY) benchmarks/reproduce.py
