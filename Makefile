# The two commands of the workspace: `make demo` and `make test` (README).
# Each creates .venv/ when missing, installs the pinned dependencies and every
# package under src/ (editable), then runs. A second call reinstalls only when
# requirements.txt, a package's setup files, config/ or launch/ changed.

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.tactex-installed
PACKAGES := $(sort $(wildcard src/*))
INSTALL_INPUTS := requirements.txt $(wildcard src/*/setup.py src/*/setup.cfg src/*/package.xml) \
	$(wildcard config/* config/*/* launch/*)
PYTEST_ARGS ?=

.PHONY: demo test bench results urdf lint clean

demo: $(STAMP)
	$(BIN)/tactex demo

test: $(STAMP)
	$(BIN)/python -m pytest $(PYTEST_ARGS)

bench: $(STAMP)
	$(BIN)/python bench/run_all.py

# Rewrite the README's generated figures from the outputs kept in bench/results/.
results: $(STAMP)
	$(BIN)/python bench/render_results.py

urdf: $(STAMP)
	$(BIN)/tactex description --write-urdf src/tactex_description/urdf/open_manipulator_x_tactile.urdf

lint: $(STAMP)
	$(BIN)/ruff check .

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(STAMP): $(BIN)/python $(INSTALL_INPUTS)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -r requirements.txt
	$(BIN)/python -m pip install --quiet --disable-pip-version-check --no-deps \
		$(addprefix -e ,$(PACKAGES))
	touch $@

clean:
	rm -rf $(VENV)
