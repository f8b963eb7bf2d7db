# colonna: two commands do all the set-up on a fresh machine.
#   make demo   creates .venv, installs colonna, runs the default study, writes a report
#   make test   creates .venv, installs colonna with test extras, runs the fast test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= out

.PHONY: demo validate test test-all bench clean

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

test: $(STAMP)
	$(BIN)/python -m pytest -q

test-all: $(STAMP)
	$(BIN)/python -m pytest -q -m ""

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_spectrum.py
	$(BIN)/python benchmarks/bench_fem.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
