# Two commands for a fresh machine: `make book` and `make test`.
# Both create .venv from environment.txt and install xnavlab (editable) first.

PYTHON ?= python3
# The environment; another beside it: `make test PYTHON=python3.13 VENV=_build/venv-3.13`
# (what `make pythons` does for each Python)
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp
WARM   := $(VENV)/.warmup-stamp
export MPLBACKEND := Agg
# pytest workers (pytest-xdist) and chapters executed at once by `make book`: one per core.
# A notebook's cells stay together on one worker (--dist loadfile): they share a kernel. The
# files go out in conftest.py's order (--no-loadscope-reorder): the reproductions' test first.
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)
XDIST  := -n $(JOBS) --dist loadfile --no-loadscope-reorder
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# Bytecode caches on (__pycache__/ is ignored by git): an environment that sets
# PYTHONDONTWRITEBYTECODE=1 makes every process compile xnavlab and the tests from source,
# 4.5 s of each pytest collection (18 s instead of 13.5 s) and 0.1 s of each kernel's imports
unexport PYTHONDONTWRITEBYTECODE

.PHONY: book book-clean test unit notebooks bench benchmarks-page lint lab clean setup warmup browser-test lab-test portability \
        check-book typed-numbers pythons

# The supported Pythons: requires-python of pyproject.toml (">=3.10,<3.14", a lower and an
# excluded upper bound). PY_CHECK is "ok" or what $(PYTHON) is; it runs on any Python, 2.7 too.
PY_RANGE := $(shell sed -n 's/^requires-python *= *"\(.*\)"$$/\1/p' pyproject.toml)
PY_CHECK = $(shell $(PYTHON) -c 'import re, sys; lo, hi = [tuple(int(n) for n in b.split(".")) for b in re.findall(r"[0-9][0-9.]*", sys.argv[1])]; print("ok" if lo <= sys.version_info[:2] < hi else "Python %d.%d.%d" % sys.version_info[:3])' '$(PY_RANGE)' 2>/dev/null || echo "not a Python that runs")
PY_OUTSIDE = PYTHON=$(PYTHON) is $(PY_CHECK); this project supports Python $(PY_RANGE) (requires-python, pyproject.toml): give PYTHON= a Python in that range
# In a recipe: stops make, one line, when $(PYTHON) is outside the range (make expands a
# recipe whole before it runs its first line: nothing is installed)
check-python = $(if $(filter ok,$(PY_CHECK)),,$(error $(PY_OUTSIDE)))

# PYTHON= given while $(VENV) exists, made by another Python: say so, rather than use the
# environment that is there and test another Python than the one asked for
ifneq ($(filter command line environment,$(origin PYTHON)),)
ifneq ($(wildcard $(BIN)/python),)
py_minor = $(shell $(1) -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)
ifneq ($(call py_minor,$(BIN)/python),$(call py_minor,$(PYTHON)))
$(error $(VENV) was made by Python $(call py_minor,$(BIN)/python), not by PYTHON=$(PYTHON) ($(or $(call py_minor,$(PYTHON)),not found)): add VENV=_build/venv-$(or $(call py_minor,$(PYTHON)),X.Y) for an environment beside it, or remove $(VENV))
endif
endif
endif

# `make book` leaves this behind when the build succeeds; browser-test rebuilds when older
# than any source of the book.
BOOK_STAMP   := _build/html/.book-stamp
BOOK_SOURCES := _config.yml _toc.yml $(wildcard book/*.ipynb book/*.md book/*.bib \
                book/_ext/*.py book/_ext/static/*) $(shell find xnavlab -name '*.py' 2>/dev/null)

setup: $(WARM)

$(STAMP): environment.txt pyproject.toml tools/jupyterlab-overrides.json
	$(if $(wildcard $(BIN)/python),,$(check-python))
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	@# uv installs environment.txt in about 25 s where pip takes about 165 s (2 cores, the same
	@# versions: compared by pip freeze); where uv cannot be had or cannot reach PyPI, pip does it
	$(BIN)/python -m pip install --quiet uv || true
	if [ -x $(BIN)/uv ] && $(BIN)/uv pip install --python $(BIN)/python --quiet -r environment.txt; then :; \
	else echo "uv did not install environment.txt: pip installs it (about three minutes)"; \
	     $(BIN)/python -m pip install --quiet -r environment.txt; fi
	@# an environment made before environment.txt held jsonschema<4.25 may still hold this (3 s an import)
	$(BIN)/python -m pip uninstall --quiet --yes rfc3987-syntax 2>/dev/null || true
	$(BIN)/python -m pip install --quiet --no-build-isolation -e .
	@# JupyterLab's defaults for this environment: every notebook cell rendered, not only those in
	@# view (windowingMode none), so that "Run All Cells" evaluates every {eval} of the prose
	@# (jupyterlab-myst reads a markdown cell's expressions from its rendering)
	mkdir -p $(VENV)/share/jupyter/lab/settings
	cp tools/jupyterlab-overrides.json $(VENV)/share/jupyter/lab/settings/overrides.json
	touch $(STAMP)

## make warmup: compile the numba kernels and cache the 30-day truth (setup runs it; again
## whenever a package source changed, so no chapter ever compiles)
$(WARM): $(STAMP) $(shell find xnavlab -name '*.py' 2>/dev/null)
	$(BIN)/python -m xnavlab warmup
	touch $(WARM)

warmup: $(WARM)

## make book: execute the chapters and render _build/html (a warning fails the build).
## Chapters execute in myst-nb's cache mode: only a chapter whose code changed runs again;
## tools/book_cache.py drops the cache when xnavlab/ or the environment changed.
# (MPLBACKEND=Agg, exported above for the tests, would stop the kernels' inline figures;
# XNAVLAB_SCRUBBER_FRAMES=1: a page executed for the book draws its sliders' HTML frames.
# BOOK_EXECUTED: the chapters make test's nbval run executed for the book, taken from there.
# tools/book_build.py is `jupyter-book build` with Sphinx on JOBS processes: 124 s against
# 149 s serial, measured 2026-11-29 on 2 cores)
book: $(WARM)
	$(BIN)/python tools/book_cache.py
	env -u MPLBACKEND $(BIN)/python tools/book_execute.py --jobs $(JOBS) $(if $(BOOK_EXECUTED),--executed $(BOOK_EXECUTED))
	env -u MPLBACKEND XNAVLAB_SCRUBBER_FRAMES=1 $(BIN)/python tools/book_build.py --jobs $(JOBS) . -W -n --keep-going
	touch $(BOOK_STAMP)

## make book-clean: forget the executed chapters and the rendered pages (next build: all)
book-clean:
	rm -rf _build/html _build/.doctrees _build/jupyter_execute _build/.jupyter_cache _build/.jupyter_cache.xnavlab-sha256

## make test: ruff over the tree; unit tests, doctests, every notebook executed by nbval; no number typed into the
## prose (tools/typed_numbers.py) and book/references.bib up to date (tools/merge_bib.py --check);
## then the book built from nothing (no execution cache: its chapters are those nbval just
## executed, as the book executes them, tools/nbval_book.py), opened in headless Chromium and its
## pages checked as a reader sees them (tools/check_book.py); then every chapter run and its
## sliders moved in JupyterLab, as a reader runs them. Chromium (for the last two) is
## installed in the background while the unit tests run, where it is missing. (The JupyterLab
## test beside the book's build and checks was measured 2026-11-29: no faster, both are
## CPU-bound on 2 cores.)
NBVAL_BOOK := _build/nbval-executed
test: $(WARM)
	@sh tools/ensure_chromium.sh --start  # apt, in the background, while the unit tests run
	$(BIN)/ruff check .
	$(BIN)/python tools/typed_numbers.py
	$(BIN)/python tools/eval_roles.py --check
	$(BIN)/python tools/hidden_names.py
	$(BIN)/python tools/merge_bib.py --check
	$(MAKE) book-clean
	rm -rf $(NBVAL_BOOK)
	XNAVLAB_NBVAL_BOOK=$(NBVAL_BOOK) $(BIN)/python -m pytest $(XDIST) --durations=25 --nbval-lax --nbval-cell-timeout=300 -p no:cacheprovider xnavlab tests book
	$(MAKE) book BOOK_EXECUTED=$(NBVAL_BOOK)
	@sh tools/ensure_chromium.sh --wait
	$(MAKE) browser-test
	$(BIN)/python tools/check_book.py --jobs $(JOBS)
	$(MAKE) lab-test

## make browser-test: every built page in headless Chromium, offline (builds the book if stale);
## one server and one Chromium per pytest worker, the pages shared out (--dist load)
browser-test: $(STAMP) $(BOOK_STAMP)
	@sh tools/ensure_chromium.sh
	XNAVLAB_BROWSER_TEST=1 $(BIN)/python -m pytest -n $(JOBS) --dist load -p no:cacheprovider tests/browser

## make lab-test: JupyterLab on 127.0.0.1 driven by headless Chromium: every chapter run, its
## explore slider moved twice, the figure checked to change; screenshots in _build/lab-screenshots.
## One JupyterLab server and one Chromium per pytest worker, the chapters shared out one at a
## time (--dist load): 338 s on 2 workers against 478 s on one, quiet machine
lab-test: $(WARM)
	@sh tools/ensure_chromium.sh
	XNAVLAB_LAB_TEST=1 $(BIN)/python -m pytest -n $(JOBS) --dist load -p no:cacheprovider tests/lab

$(BOOK_STAMP): $(WARM) $(BOOK_SOURCES)
	$(MAKE) book

## make check-book: the built pages as a reader sees them (builds the book if stale): broken
## tables, verdicts outside PASS / NOT CLAIMED / FAIL, stray | or $, unresolved references and
## glue, missing images, empty outputs, exercises without a collapsed executed solution
check-book: $(STAMP) $(BOOK_STAMP)
	$(BIN)/python tools/check_book.py --jobs $(JOBS)

## make typed-numbers: every number typed into the book's prose that is neither glued nor in
## tools/typed_numbers_allow.txt (python tools/typed_numbers.py book/NN_x.ipynb: one page)
typed-numbers: $(STAMP)
	$(BIN)/python tools/typed_numbers.py

unit: $(WARM)
	$(BIN)/python -m pytest $(XDIST) -p no:cacheprovider xnavlab tests

notebooks: $(WARM)
	$(BIN)/python -m pytest $(XDIST) --nbval-lax --nbval-cell-timeout=300 -p no:cacheprovider book

## make bench: every benchmark (bench_against.py needs --base REV: run it by hand), then the page
bench: $(STAMP)
	for f in benchmarks/bench_*.py; do [ $$f = benchmarks/bench_against.py ] || $(BIN)/python $$f || exit 1; done
	$(MAKE) benchmarks-page

## make benchmarks-page: benchmarks/README.md rendered from benchmarks/results/*.json
benchmarks-page:
	$(BIN)/python benchmarks/report.py

## make lint: ruff over the whole tree, the chapters and tools included (make test runs it)
lint: $(STAMP)
	$(BIN)/ruff check .

## make lab: open the chapters in JupyterLab
lab: $(STAMP)
	env -u MPLBACKEND $(BIN)/jupyter lab book

## make portability: the numeric tests under three OpenBLAS kernel families in turn (a test
## that decides on a rounding-level number fails here on some family)
portability: $(WARM)
	for core in Haswell Sandybridge Prescott; do \
	  echo "== OPENBLAS_CORETYPE=$$core"; \
	  OPENBLAS_CORETYPE=$$core $(BIN)/python -m pytest $(XDIST) -q -p no:cacheprovider xnavlab tests || exit 1; \
	done

## make pythons: the unit tests, doctests and notebooks under every supported Python found on
## this machine (python3.X on PATH or a pyenv version), each in its own environment
## _build/venv-3.X (`make clean` removes them); says which versions it skipped and, per
## version, the passed / failed / skipped counts and the wall time (tools/pythons.sh)
pythons:
	@sh tools/pythons.sh '$(PY_RANGE)' '$(MAKE)'

clean:
	rm -rf _build
