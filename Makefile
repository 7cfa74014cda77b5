# Two commands: `make demo` (set up, build the FMU, run the demo scenes) and `make test` (the tests and
# the documentation site's strict build); `make docs` builds the site into site/.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: setup fmu demo test test-fast docs clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

setup: $(STAMP)

fmu: setup
	$(BIN)/python -m build_fmu

demo: setup
	$(BIN)/pidamper demo

test: setup
	$(BIN)/lint-imports
	PYTHONFAULTHANDLER=1 $(BIN)/python -m pytest
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir $(VENV)/site-check

docs: setup
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

test-fast: setup
	$(BIN)/python -m pytest -m "not slow"

clean:
	rm -rf $(VENV) dist out site .pytest_cache
