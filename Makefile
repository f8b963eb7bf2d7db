# colonna: two commands do all the set-up on a fresh machine.
#   make demo   creates .venv, installs colonna, runs the default study, writes a report
#   make test   creates .venv, installs colonna with test extras, runs the fast test suite
#   make test-rounding  the tests of chaotic numbers under K seeded ulp perturbations (docs/testing.md)
#   make lint   ruff and mypy over the code (the same .venv)
#   make docs   the documentation site (Sphinx), warnings as errors, into docs/_build/html
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= out

.PHONY: demo validate test test-all test-rounding lint bench clean browser coverage docs docs-numbers

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	@# setuptools warns on every editable install of folders mapped to other package names
	@# (rigid/ -> colonna.rigid), which this layout does on purpose: that one notice is hidden
	PYTHONWARNINGS="ignore::UserWarning" $(BIN)/python -m pip install --quiet -e '.[test,lint]'
	@# compile the kernels into numba's cache once, so that no first run pays for it
	$(BIN)/colonna warmup
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/colonna study default --out $(OUT)/demo
	@echo "report: $(OUT)/demo/index.html"

validate: $(STAMP)
	$(BIN)/colonna validate --out $(OUT)/validation

# The report-render and PDF tests need a headless browser and poppler (pdftotext, pdftoppm):
# installed where apt-get can (as root); the tests that need them are skipped elsewhere.
BROWSER := $(shell command -v chromium || command -v chromium-browser || command -v google-chrome)
MISSING := $(strip $(if $(BROWSER),,chromium) $(if $(shell command -v pdftoppm),,poppler-utils))

browser:
ifneq ($(MISSING),)
	@if command -v apt-get >/dev/null 2>&1 && [ "$$(id -u)" = 0 ]; then \
	  echo "installing $(MISSING) for the report tests"; \
	  (apt-get install -y -q $(MISSING) >/dev/null 2>&1 || \
	   (apt-get update -q >/dev/null 2>&1 && apt-get install -y -q $(MISSING) >/dev/null 2>&1)) \
	  || echo "$(MISSING) not installed: the tests that need them will be skipped"; \
	else echo "$(MISSING) missing and no apt-get as root: the tests that need them will be skipped"; fi
endif

test: $(STAMP) browser
	$(BIN)/python -m pytest -q

test-all: $(STAMP) browser
	$(BIN)/python -m pytest -q -m ""

# The rounding stress mode (docs/testing.md): every fast test marked chaotic once per seed 1 .. K,
# each ground motion moved in its last bits and each FEM replica's start as seeded, then once
# more with the kernels compiled for a generic processor; ROUNDING_MARK=chaotic adds the slow ones
ROUNDING_K    ?= 8
ROUNDING_MARK ?= chaotic and not slow

test-rounding: $(STAMP)
	@for k in $$(seq 1 $(ROUNDING_K)); do \
	  echo "rounding seed $$k of $(ROUNDING_K)"; \
	  $(BIN)/python -m pytest -q -m "$(ROUNDING_MARK)" --rounding-seed $$k || exit 1; \
	done
	NUMBA_CPU_NAME=generic $(BIN)/python -m pytest -q -m "$(ROUNDING_MARK)"

# branch coverage of studies/ by the default test suite (docs/testing.md): .coverage, a table
coverage: $(STAMP) browser
	$(BIN)/coverage run --branch --source=studies -m pytest -q
	$(BIN)/coverage report --skip-covered
	$(BIN)/coverage json -q -o coverage.json
	@$(BIN)/python -c "import json; t = json.load(open('coverage.json'))['totals']; \
	print(f\"studies/ branches covered: {t['covered_branches']} of {t['num_branches']} \
	({100 * t['covered_branches'] / t['num_branches']:.1f} %)\")"

# ruff (lint + format check) and mypy, as configured in pyproject.toml; .ci/run runs it
lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy

# The documentation site: Sphinx with MyST Markdown and sphinx-gallery (the docs extra, installed
# into the same .venv), warnings as errors; the gallery's examples run at every build.
DOCS_STAMP := $(VENV)/.docs-installed

$(DOCS_STAMP): $(STAMP)
	PYTHONWARNINGS="ignore::UserWarning" $(BIN)/python -m pip install --quiet -e '.[docs]'
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)
	MPLBACKEND=Agg $(BIN)/sphinx-build -W --keep-going -q -b html docs docs/_build/html
	@echo "documentation: docs/_build/html/index.html"

# The numbers the documentation quotes from the shipped studies (docs/runs/*.json), from fresh
# runs of them; make docs refuses a record made from another study file or version.
docs-numbers: demo
	$(BIN)/colonna study free-rocking --out $(OUT)/free-rocking
	$(BIN)/python docs/run_numbers.py default $(OUT)/demo
	$(BIN)/python docs/run_numbers.py free-rocking $(OUT)/free-rocking

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_spectrum.py
	$(BIN)/python benchmarks/bench_fem.py
	$(BIN)/python benchmarks/bench_cohesive.py
	$(BIN)/python benchmarks/bench_ensemble.py
	$(BIN)/python benchmarks/bench_multibody.py
	$(BIN)/python benchmarks/bench_plastic_collars.py
	$(BIN)/python benchmarks/bench_spectrum_crosscheck.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache docs/_build docs/generated docs/gallery docs/sg_execution_times.rst
