# Thin wrapper around CMake. `make run` and `make test` install what is
# missing (Debian 12 packages), configure, build, then run.
BUILD_DIR ?= build
BUILD_TYPE ?= RelWithDebInfo
JOBS ?= $(shell nproc)
ADDR ?= 127.0.0.1:50051
GENERATOR := $(shell command -v ninja >/dev/null 2>&1 && echo "-G Ninja")
# Our code builds warning-free on Debian 12's GCC; a warning fails the build
# here and in CI (`make WERROR=OFF ...` for another compiler).
WERROR ?= ON

.PHONY: all deps configure build run test clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ]; then \
	  cmake -S . -B $(BUILD_DIR) $(GENERATOR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	    -DGISTREAM_WERROR=$(WERROR); fi

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Starts gistreamd on the bundled scenes, streams the Cornell box with a
# moving light and an orbiting camera into out/ with global illumination
# (implicit_visibility, scenes/cornell_orbit.json), prints the timing table.
run: build
	@bash scripts/run-demo.sh $(BUILD_DIR) $(ADDR)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD_DIR) out
