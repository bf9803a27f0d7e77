# The two commands of the README. Both create .venv on first use and are cheap to re-run:
# the install step is redone only when pyproject.toml changes.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT := demo-output

.PHONY: demo test docs bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test,docs]'
	touch $@

# The demo query: from the middle of the left room's floor to the right half of the right room's floor,
# across the corridor (the start spans four segments of P′: one plan must work from all of them).
# two_rooms is a shipped model: every command takes a model's name where it expects an environment file.
DEMO_ENV := two_rooms
DEMO_QUERY := --from e0:0.2:0.8 --to e4:0.5:1

demo: $(VENV)/.installed
	@mkdir -p $(OUT)
	$(BIN)/solverplan plan $(DEMO_ENV) $(DEMO_QUERY) --pareto --format text
	$(BIN)/solverplan plan $(DEMO_ENV) $(DEMO_QUERY) --objective tolerance -o $(OUT)/plan.json --certificate $(OUT)/certificate.json
	$(BIN)/solverplan plan $(DEMO_ENV) $(DEMO_QUERY) --objective tolerance --format text
	$(BIN)/solverplan verify $(OUT)/certificate.json --env $(DEMO_ENV) $(DEMO_QUERY) --format text
	$(BIN)/solverplan simulate $(DEMO_ENV) $(OUT)/plan.json --trials 10000 --seed 1 --sampling endpoints --format text
	$(BIN)/solverplan render $(DEMO_ENV) --plan $(OUT)/plan.json --trajectories 100 --edge-ids -o $(OUT)/plan.png
	$(BIN)/solverplan report $(DEMO_ENV) --plan $(OUT)/plan.json --certificate $(OUT)/certificate.json -o $(OUT)/report.html
	@echo "demo: wrote $(OUT)/plan.json, $(OUT)/certificate.json (verified), $(OUT)/plan.png and $(OUT)/report.html"

test: $(VENV)/.installed
	$(BIN)/python -m pytest -q -n auto --dist loadfile
	$(BIN)/python -m mypy
	$(MAKE) --no-print-directory docs

# The documentation site: docs/_build/html, with site/ pointing at it. Always a full build (-E, and the gallery
# re-runs every example), so the pages show what this tree answers; warnings are errors.
DOCS_OUT := docs/_build/html

docs: $(VENV)/.installed
	rm -rf docs/generated  # autosummary's pages of names since renamed or unexported would warn (not in a toctree)
	$(BIN)/python -m sphinx -b html -E -W --keep-going -q docs $(DOCS_OUT)
	ln -sfn $(DOCS_OUT) site
	@echo "docs: open site/index.html"

bench: $(VENV)/.installed
	$(BIN)/python benchmarks/bench_raycast.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .hypothesis .mypy_cache site docs/_build docs/generated docs/auto_examples docs/api.rst docs/tutorial/out
