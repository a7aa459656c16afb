# Two commands do all the set-up on a fresh Debian 12 machine:
#   make render   install what is missing, build, render scenes/cornell_box.json into out/
#   make test     the same set-up, then every test (ctest + pytest)
# A second run with nothing changed rebuilds nothing.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
# The cmake/ctest that pip puts in the venv: called by path, never from PATH.
CTEST := $(CURDIR)/$(VENV)/bin/ctest
BUILD := build/py
BIN := $(BUILD)/cpp/pellucid-render
# Everything beyond make, git and python3 that a minbase Debian 12 lacks: the compiler, venv and the
# Python headers, the libraries, and openimageio-tools (OpenImageIO's CMake package file names its
# binaries, and --no-install-recommends would leave them out).
DEB_PACKAGES := g++ python3-venv python3-dev ca-certificates \
                libembree-dev libopenimageio-dev openimageio-tools libglm-dev libtbb-dev \
                nlohmann-json3-dev libpugixml-dev libtinyobjloader-dev libgtest-dev libxsimd-dev libcli11-dev
PY_DEPS := "pybind11>=2.12" "pybind11-stubgen" "scikit-build-core>=0.10" "numpy" "pytest" "cmake>=3.18" "ninja" "matplotlib" "tqdm" \
           "nbclient" "nbformat" "ipykernel"
# The `docs` extra of pyproject.toml, read from there: `make docs` needs it, and the tests build the
# API reference with it (tests/python/test_api_docs.py).
DOCS_DEPS = $(shell $(PYTHON) -c 'import tomllib; print(" ".join(repr(d) for d in tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"]["docs"]))')
SOURCES := $(shell find cpp bindings python tests/cpp cmake -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.py' -o -name '*.txt' -o -name '*.cmake' -o -name '*.pyi' \) 2>/dev/null) CMakeLists.txt pyproject.toml

.PHONY: render test deps docs clean sanitize
.DEFAULT_GOAL := render

# Debian packages: installed only when one is missing (needs root or sudo).
$(VENV)/.deb-stamp: Makefile
	@missing=$$(for p in $(DEB_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages: $$missing"; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi
	@mkdir -p $(VENV) && touch $@

$(VENV)/.py-stamp: $(VENV)/.deb-stamp pyproject.toml
	@test -x $(VPY) || $(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q $(PY_DEPS) $(DOCS_DEPS)
	@touch $@

# Editable, incremental install: the CMake build in build/py also builds pellucid-render and the
# tests (which a plain `pip install .` leaves out).
$(VENV)/.install-stamp: $(VENV)/.py-stamp $(SOURCES)
	$(VPY) -m pip install -q --no-build-isolation -e . -Cbuild-dir=$(BUILD) \
	  -Ccmake.define.PELLUCID_BUILD_TESTS=ON
	@touch $@

deps: $(VENV)/.install-stamp

render: deps
	@mkdir -p out
	$(BIN) scenes/cornell_box.json -o out/cornell_box.exr -o out/cornell_box.png
	@echo "rendered: $(CURDIR)/out/cornell_box.exr and $(CURDIR)/out/cornell_box.png"

test: deps
	cd $(BUILD) && $(CTEST) --output-on-failure -j2
	$(VPY) -m pytest -q

# The documentation site in build/docs: the Markdown pages of docs/, the tutorial notebooks (shown with
# their stored outputs, not run) and the API reference, which is read from the Python sources and
# python/pellucid/_core.pyi, so nothing is compiled for it.
docs: $(VENV)/.py-stamp
	$(VPY) -m sphinx -b html -q --keep-going docs build/docs
	@echo "documentation: $(CURDIR)/build/docs/index.html"

# The core and the C++ tests built with AddressSanitizer + UndefinedBehaviorSanitizer in their own
# build directory (-O1, no Python module, no executable), then the C++ tests there. Any finding
# (leaks included) fails the test that triggers it. Skipped: the statistical tests that run the
# code of faster tests millions of times (BxDF chi-square and furnace suites, bumped chi-square and
# weight checks, phase chi-square, medium furnace, closed-sphere and Sobol error renders, image
# agreement). Run by hand (ctest -R with this list in build/sanitize), the 151 of them that existed
# then took about 35 core-minutes and were clean. The cheaper statistical families run here: warp,
# light and VNDF chi-square, the other bumped properties, Kulla-Conty and rough-coat tables, furnace
# spheres, Russian roulette (about 5 core-minutes).
SAN_BUILD := build/sanitize
SAN_SKIP := BxDFProperties\.(Chi2|WhiteFurnace)|BumpedProperties\.(Chi2|WeightEquals)|PhaseFunction\.Chi2|MediaRender\.AlbedoOne|ClosedSphereFromInside|SobolRender\.(LowerError|BitIdentical)|PathLanes\.Agrees|SameImageAsOnePathAtATime/[tvem]
sanitize: $(VENV)/.py-stamp
	$(VENV)/bin/cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_MAKE_PROGRAM=$(CURDIR)/$(VENV)/bin/ninja \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
	  -DPELLUCID_SANITIZE=address,undefined -DPELLUCID_BUILD_PYTHON=OFF -DPELLUCID_BUILD_APP=OFF
	$(VENV)/bin/cmake --build $(SAN_BUILD) -j2
	cd $(SAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 $(CTEST) --output-on-failure -j2 -E '$(SAN_SKIP)'

clean:
	rm -rf build out $(VENV)
