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
# (leaks included) fails the test that triggers it. The sanitizers slow renders about 40-fold, so
# this runs the code paths, not the statistics: skipped are the tests that run the code of faster
# tests many times over, each 11 s to over 5 minutes on a busy 2-core machine (BxDF chi-square and furnace
# suites, bumped chi-square, weight, pdf-integral and furnace checks, phase chi-square, the medium
# furnaces, integrals and grid agreements, the closed-sphere and closed-box renders, the Sobol error
# renders, the image and strategy agreements, Russian roulette, thread-count determinism, light
# selection with delta lights, Kulla-Conty furnaces, the Cornell-box resume, the larger lane-record
# and chunking renders). Every one of them ran clean under the sanitizers in full runs before.
# What runs: every family with at least its cheaper members (the warp, light and
# VNDF chi-square tests, the lane and packet-form tests, the film, resume, media, subsurface and
# scene tests): 518 tests in about 5 minutes on 2 cores, after a build of 12 minutes.
# On x86-64 the path tracer is built for its AVX2 target only (and the scalar one, always built):
# the AVX-512 and SSE4.2 targets instantiate the same templates at other widths, and their kernels
# and lane probes were a third of the sanitized build's compile time (cmake/PellucidOptions.cmake,
# PELLUCID_KERNEL_TARGETS).
SAN_BUILD := build/sanitize
SAN_TARGETS := $(if $(filter x86_64,$(shell uname -m)),-DPELLUCID_KERNEL_TARGETS=avx2)
SAN_SKIP := BxDFProperties\.(Chi2|WhiteFurnace)|BumpedProperties\.(Chi2|WeightEquals|PdfIntegrates|WhiteFurnace)|PhaseFunction\.Chi2|MediaRender\.(AlbedoOne|FurnaceWithoutMediumNEE|InfiniteEmitting|DiffuseCoreInAFurnace|SingleScatteringInAThinSlab)|Closed(Sphere|MeshBox)FromInside|SobolRender\.(LowerError|BitIdentical)|PathLanes\.Agrees|SameImageAsOnePathAtATime/[tvem]|SimdTargetRender\.(ShapeTableLanes|TexLanesEqual|ChunksOfWholePixels|PacketFormsEqualBSDFLanes)|Strategies\.AgreePixelByPixel|RussianRoulette\.UnbiasedInClosedSphere|Determinism\.BitIdenticalAcrossThreadCounts|KullaConty(Dielectric)?\.(CompensatedWhiteFurnace|TableMatchesMonteCarlo)|Resume\.CornellBox|Medium\.(ConstantGridAgrees|RatioAndDeltaTracking)|DeltaLights\.|RoughCoatTable\.AgreesWith|ProfileAccuracy\.ThinSlab|SubsurfaceRender\.(RandomWalkInALossless|HalfSpaceUnderUniformLight)|LightChi2\.(AreaSphereFromInside|EnvmapOnAnEqualArea)|FilmSplat\.(SameImageAsFilterSampling|VarianceMatchesSpread)|FootprintNeed\.Skipping
sanitize: $(VENV)/.py-stamp
	$(VENV)/bin/cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_MAKE_PROGRAM=$(CURDIR)/$(VENV)/bin/ninja \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
	  -DPELLUCID_SANITIZE=address,undefined -DPELLUCID_BUILD_PYTHON=OFF -DPELLUCID_BUILD_APP=OFF $(SAN_TARGETS)
	$(VENV)/bin/cmake --build $(SAN_BUILD) -j2
	cd $(SAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 $(CTEST) --output-on-failure -j2 -E '$(SAN_SKIP)'

clean:
	rm -rf build out $(VENV)
