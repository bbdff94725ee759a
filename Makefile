# Thin wrapper around CMake. `make run` and `make test` install what is
# missing (Debian 12 packages), configure, build, then run.
BUILD_DIR ?= build
BUILD_TYPE ?= RelWithDebInfo
# RelWithDebInfo's debug information: line tables only (-g1: backtraces and
# sanitizer reports with file:line, no variables), which compiles about a
# quarter faster than -g (CI's build, docs/RESULTS.md "CI time"). For a
# debugger: `make DEBUG_INFO=-g` in a fresh BUILD_DIR.
DEBUG_INFO ?= -g1
JOBS ?= $(shell nproc)
ADDR ?= 127.0.0.1:50051
GENERATOR := $(shell command -v ninja >/dev/null 2>&1 && echo "-G Ninja")
# Our code builds warning-free on Debian 12's GCC; a warning fails the build
# here and in CI (`make WERROR=OFF ...` for another compiler).
WERROR ?= ON

# `make image`: the container image (deploy/Dockerfile) with podman, else
# docker. ENGINE_OPTS go before `build` (e.g. --runtime runc), BUILD_OPTS
# after it (e.g. --network host); deploy/README.md has what a sandbox needs.
# CONTEXT: the source tree to build (default this one; e.g. a `git archive`).
IMAGE ?= gistream/gistreamd:latest
CONTEXT ?= .
ENGINE ?= $(shell command -v podman >/dev/null 2>&1 && echo podman || echo docker)

.PHONY: all deps configure build run test clean image format

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ]; then \
	  cmake -S . -B $(BUILD_DIR) $(GENERATOR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 $(DEBUG_INFO) -DNDEBUG" \
	    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 $(DEBUG_INFO) -DNDEBUG" \
	    -DGISTREAM_WERROR=$(WERROR); fi

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Starts gistreamd on the bundled scenes, streams the Cornell box with a
# moving light and an orbiting camera into out/ with global illumination
# (implicit_visibility, scenes/cornell_orbit.json), prints the timing table.
run: build
	@bash scripts/run-demo.sh $(BUILD_DIR) $(ADDR)

# One ctest entry per GoogleTest suite (cmake/GTestSuites.cmake); afterwards
# the 20 slowest entries and cases (scripts/test_times.py, from the JUnit
# and GoogleTest XML in $(BUILD_DIR)/test-results/).
test: build
	@rm -rf $(BUILD_DIR)/test-results/*.xml
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) \
	  --output-junit test-results/ctest.xml; status=$$?; \
	  python3 $(CURDIR)/scripts/test_times.py . 20; exit $$status

# Reformats our C++ with .clang-format (the `format` test checks it).
format:
	@bash scripts/format.sh --fix

# COMMIT: the commit built, shown by --version (default this checkout's
# HEAD; set it when CONTEXT is another tree).
COMMIT ?= $(shell git rev-parse --short=12 HEAD 2>/dev/null)
image:
	$(ENGINE) $(ENGINE_OPTS) build $(BUILD_OPTS) --build-arg GISTREAM_COMMIT=$(COMMIT) \
	  -f $(CONTEXT)/deploy/Dockerfile -t $(IMAGE) $(CONTEXT)

clean:
	rm -rf $(BUILD_DIR) out
