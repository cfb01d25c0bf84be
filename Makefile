# reducerlab: `make demo` and `make test` are all a fresh machine needs (Python 3.11).
PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
DEMO_DIR ?= demo-output
SCREENSHOTS_DIR ?= screenshots-output
# test processes (pytest-xdist; files stay whole on one worker, so module fixtures are
# built once): 2 fits the 2-core, 24 GB machines the suite is sized for
TEST_JOBS ?= 2

.PHONY: demo test lint clean screenshots

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

# every report figure screenshot in headless Chromium, checked not blank and offline
# (issue 32): contact sheets and index.md in $(SCREENSHOTS_DIR)
screenshots: $(STAMP)
	@command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || \
	if [ "$$(id -u)" = 0 ]; then apt-get update -q && apt-get install -y -q chromium; \
	else echo "screenshots: chromium is missing; install it as root: apt-get install -y chromium" >&2; exit 2; fi
	MPLBACKEND=Agg $(BIN)/python benchmarks/screenshots.py -o $(SCREENSHOTS_DIR)

clean:
	rm -rf $(VENV) $(DEMO_DIR) $(SCREENSHOTS_DIR) .pytest_cache .ruff_cache
