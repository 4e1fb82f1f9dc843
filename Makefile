# Two commands for a fresh machine: `make book` and `make test`.
# Both create .venv from environment.txt and install xnavlab (editable) first.

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp
export MPLBACKEND := Agg
export PYDEVD_DISABLE_FILE_VALIDATION := 1

.PHONY: book test unit notebooks bench lint lab clean setup

setup: $(STAMP)

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r environment.txt
	$(BIN)/python -m pip install --quiet --no-build-isolation -e .
	touch $(STAMP)

## make book: execute every chapter and render _build/html (a warning fails the build)
book: $(STAMP)
	$(BIN)/jupyter-book build . -W -n --keep-going

## make test: unit tests, doctests, and every notebook executed by nbval
test: $(STAMP)
	$(BIN)/python -m pytest --nbval-lax -p no:cacheprovider xnavlab tests book

unit: $(STAMP)
	$(BIN)/python -m pytest -p no:cacheprovider xnavlab tests

notebooks: $(STAMP)
	$(BIN)/python -m pytest --nbval-lax -p no:cacheprovider book

bench: $(STAMP)
	for f in benchmarks/bench_*.py; do $(BIN)/python $$f || exit 1; done

lint: $(STAMP)
	$(BIN)/ruff check xnavlab tests benchmarks

## make lab: open the chapters in JupyterLab
lab: $(STAMP)
	$(BIN)/jupyter lab book

clean:
	rm -rf _build
