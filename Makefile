# The two commands of the README. Both create .venv on first use and are cheap to re-run:
# the install step is redone only when pyproject.toml changes.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT := demo-output

.PHONY: demo test bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed
	@mkdir -p $(OUT)
	$(BIN)/solverplan info models/two_rooms.json --format text
	$(BIN)/solverplan render models/two_rooms.json --edge-ids -o $(OUT)/two_rooms.png
	@echo "demo: wrote $(OUT)/two_rooms.png"

test: $(VENV)/.installed
	$(BIN)/python -m pytest -q

bench: $(VENV)/.installed
	$(BIN)/python benchmarks/bench_raycast.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .hypothesis
