# reducerlab: `make demo` and `make test` are all a fresh machine needs (Python 3.11).
PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
DEMO_DIR ?= demo-output
# test processes (pytest-xdist; files stay whole on one worker, so module fixtures are
# built once): 2 fits the 2-core, 24 GB machines the suite is sized for
TEST_JOBS ?= 2

.PHONY: demo test lint clean

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	MPLBACKEND=Agg $(BIN)/python scripts/warm_kernels.py
	touch $(STAMP)

demo: $(STAMP)
	MPLBACKEND=Agg $(BIN)/reducerlab demo -o $(DEMO_DIR)

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

test: $(STAMP) lint
	MPLBACKEND=Agg $(BIN)/python -m pytest -n $(TEST_JOBS) --dist loadfile

clean:
	rm -rf $(VENV) $(DEMO_DIR) .pytest_cache .ruff_cache
