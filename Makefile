# Every target works from a fresh clone: it creates .venv through `setup` when needed.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: setup generate regenerate test bench lint demo docs clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,plot,docs]"
	touch $(STAMP)

# the packages that are out of date (a changed mechanism file or generator); regenerate: all
generate: $(STAMP)
	$(BIN)/python -m parakin.generator

regenerate: $(STAMP)
	$(BIN)/python -m parakin.generator --force

demo: generate
	$(BIN)/parakin demo

test: $(STAMP)
	$(BIN)/python -m pytest -n auto --durations=15

bench: $(STAMP)
	$(BIN)/python -m bench

lint: $(STAMP)
	$(BIN)/ruff check parakin generator mechanisms tests bench examples
	$(BIN)/ruff format --check parakin generator mechanisms tests bench examples
	$(BIN)/mypy

# the documentation site into site/, warnings as errors: runs the tutorials' code, the notebooks
# and examples/ (docs/hooks/gallery.py), so a snippet that stopped working fails the build
docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/mkdocs build --strict

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache build
