# The two commands of the workspace: `make demo` and `make test` (README).
# Each creates .venv/ when missing, installs the pinned dependencies and every Python
# package under src/ (editable), builds the interface package tactex_msgs into .venv/,
# then runs. A second call reinstalls only when requirements.txt, a package's setup
# files, config/ or launch/ changed, and rebuilds tactex_msgs only when its interface
# files, CMakeLists.txt, package.xml, its build script or requirements.txt changed.

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.tactex-installed
MSGS_STAMP := $(VENV)/.tactex-msgs-built
PACKAGES := $(patsubst %/setup.py,%,$(sort $(wildcard src/*/setup.py)))
INSTALL_INPUTS := requirements.txt $(wildcard src/*/setup.py src/*/setup.cfg) \
	$(addsuffix /package.xml,$(PACKAGES)) $(wildcard config/* config/*/* launch/*)
MSGS_INPUTS := $(wildcard src/tactex_msgs/msg/*.msg src/tactex_msgs/srv/*.srv \
	src/tactex_msgs/action/*.action) src/tactex_msgs/CMakeLists.txt \
	src/tactex_msgs/package.xml tools/build_interfaces.py
PYTEST_ARGS ?=
DEMO_ARGS ?=

.PHONY: demo test hunt bench results urdf lint clean

demo: $(STAMP) $(MSGS_STAMP)
	$(BIN)/tactex demo $(DEMO_ARGS)

test: $(STAMP) $(MSGS_STAMP)
	$(BIN)/python -m pytest $(PYTEST_ARGS)

# The hard-case property suite with fresh random examples (`make test` draws a fixed set).
hunt: $(STAMP)
	$(BIN)/python -m pytest -q -m hard_case tests --hypothesis-profile=hunt $(PYTEST_ARGS)

bench: $(STAMP) $(MSGS_STAMP)
	$(BIN)/python bench/run_all.py

# Rewrite the docs' generated figures (docs/*/*.md) from the outputs kept in bench/results/.
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

# tactex_msgs (ament_cmake + rosidl) built with plain CMake from the wheels in .venv/;
# tools/build_interfaces.py checks the tools first and names a missing one. Rebuilt when
# an interface input or requirements.txt changes, not on every reinstall of $(STAMP).
$(MSGS_STAMP): $(MSGS_INPUTS) requirements.txt | $(STAMP)
	$(BIN)/python tools/build_interfaces.py
	touch $@

clean:
	rm -rf $(VENV)
