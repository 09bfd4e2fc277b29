# The two commands of the README: `make demo` (main job) and `make test` (the test suite).
# Both install whatever is missing first (scripts/bootstrap.sh) and are idempotent.
VENV := .venv
BIN := $(VENV)/bin
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1
export MPLBACKEND := Agg

.PHONY: demo figures test lint format bootstrap

bootstrap:
	@scripts/bootstrap.sh

demo: bootstrap
	$(BIN)/knitmech run -o results

# the docs' figures and printed table of the default scene, from the current code (empty cache)
figures: bootstrap
	$(BIN)/python scripts/docs_figures.py

lint: bootstrap
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

# two workers (pytest-xdist), one per core of the CI machines; a module's tests stay on one
# worker, so its module-scoped fixtures are computed once
test: lint
	$(BIN)/python -m pytest -n 2 --dist loadscope

format: bootstrap
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .
