# colonna: two commands do all the set-up on a fresh machine.
#   make demo   creates .venv, installs colonna, runs the default study, writes a report
#   make test   creates .venv, installs colonna with test extras, runs the fast test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= out

.PHONY: demo validate test test-all bench clean browser

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/colonna study default --out $(OUT)/demo
	@echo "report: $(OUT)/demo/index.html"

validate: $(STAMP)
	$(BIN)/colonna validate --out $(OUT)/validation

# The report-render test needs a headless browser: installed where apt-get can (as root).
BROWSER := $(shell command -v chromium || command -v chromium-browser || command -v google-chrome)

browser:
ifeq ($(BROWSER),)
	@if command -v apt-get >/dev/null 2>&1 && [ "$$(id -u)" = 0 ]; then \
	  echo "installing chromium for the report-render test"; \
	  (apt-get install -y -q chromium >/dev/null 2>&1 || \
	   (apt-get update -q >/dev/null 2>&1 && apt-get install -y -q chromium >/dev/null 2>&1)) \
	  || echo "chromium not installed: the report-render test will be skipped"; \
	else echo "no chromium and no apt-get as root: the report-render test will be skipped"; fi
endif

test: $(STAMP) browser
	$(BIN)/python -m pytest -q

test-all: $(STAMP) browser
	$(BIN)/python -m pytest -q -m ""

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_spectrum.py
	$(BIN)/python benchmarks/bench_fem.py
	$(BIN)/python benchmarks/bench_ensemble.py
	$(BIN)/python benchmarks/bench_multibody.py
	$(BIN)/python benchmarks/bench_spectrum_crosscheck.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
