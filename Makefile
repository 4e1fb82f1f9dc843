# Two commands for a fresh machine: `make book` and `make test`.
# Both create .venv from environment.txt and install xnavlab (editable) first.

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp
export MPLBACKEND := Agg
export PYDEVD_DISABLE_FILE_VALIDATION := 1

.PHONY: book test unit notebooks bench lint lab clean setup browser-test

# `make book` leaves this behind when the build succeeds; browser-test rebuilds when older
# than any source of the book.
BOOK_STAMP   := _build/html/.book-stamp
BOOK_SOURCES := _config.yml _toc.yml $(wildcard book/*.ipynb book/*.md book/*.bib \
                book/_ext/*.py book/_ext/static/*) $(wildcard xnavlab/*.py xnavlab/reproductions/*.py)

setup: $(STAMP)

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r environment.txt
	$(BIN)/python -m pip install --quiet --no-build-isolation -e .
	touch $(STAMP)

## make book: execute every chapter and render _build/html (a warning fails the build)
# (MPLBACKEND=Agg, exported above for the tests, would stop the kernels' inline figures)
book: $(STAMP)
	env -u MPLBACKEND $(BIN)/jupyter-book build . -W -n --keep-going
	touch $(BOOK_STAMP)

## make test: unit tests, doctests, and every notebook executed by nbval
test: $(STAMP)
	$(BIN)/python -m pytest --nbval-lax --nbval-cell-timeout=300 -p no:cacheprovider xnavlab tests book
	$(MAKE) browser-test

## make browser-test: every built page in headless Chromium, offline (builds the book if stale)
browser-test: $(STAMP) $(BOOK_STAMP)
	@sh tools/ensure_chromium.sh
	XNAVLAB_BROWSER_TEST=1 $(BIN)/python -m pytest -p no:cacheprovider tests/browser

$(BOOK_STAMP): $(STAMP) $(BOOK_SOURCES)
	$(MAKE) book

unit: $(STAMP)
	$(BIN)/python -m pytest -p no:cacheprovider xnavlab tests

notebooks: $(STAMP)
	$(BIN)/python -m pytest --nbval-lax --nbval-cell-timeout=300 -p no:cacheprovider book

bench: $(STAMP)
	for f in benchmarks/bench_*.py; do $(BIN)/python $$f || exit 1; done

lint: $(STAMP)
	$(BIN)/ruff check xnavlab tests benchmarks

## make lab: open the chapters in JupyterLab
lab: $(STAMP)
	env -u MPLBACKEND $(BIN)/jupyter lab book

clean:
	rm -rf _build
