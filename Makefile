# terralod — the two commands that do everything on a fresh Debian 12 machine:
#   make demo   install the program's dependencies, build it, turn the bundled default DEM
#               (with its Landsat image draped over it) into a tileset, describe, verify and
#               render it (an overview and the first frames of the automatic flight),
#               then benchmark part of the flight against the source
#   make test   install dependencies, build, run every test (the loader's under ThreadSanitizer,
#               the readers' under AddressSanitizer + UndefinedBehaviorSanitizer, and every
#               fuzz target briefly)
PRESET ?= release
BUILD_DIR := build/$(PRESET)
TERRALOD := $(BUILD_DIR)/apps/terralod/terralod
DEMO_DEM := tests/data/zion_srtm3_utm12_30m.tif
DEMO_IMAGE := tests/data/zion_landsat8_rgb_utm12_30m.tif
DEMO_DIR := build/demo
# One compiler per core. Against Ninja's default (cores + 2) on 2 cores, in clean make test runs:
# the release build 274 and 292 s against 288 s (no gain), the sanitizer builds 33 + 96 s
# against 40 + 113 s (clang's instrumented units crowd each other out of the caches).
JOBS ?= $(shell nproc)

.PHONY: all deps deps-demo configure configure-app build app demo test test-tsan test-sanitize test-asan format check-format clean

all: build

deps:
	./scripts/install-deps.sh

# Only what building and running terralod needs: no test, benchmark or sanitizer packages.
deps-demo:
	./scripts/install-deps.sh --demo

# make app configures the build without tests and benchmarks (whose packages deps-demo does not
# install); configure turns them on again. Neither option changes how terralod itself compiles,
# so switching between the two rebuilds nothing.
configure: deps
	cmake --preset $(PRESET) $(if $(filter release debug,$(PRESET)),-DTERRALOD_BUILD_TESTS=ON -DTERRALOD_BUILD_BENCH=ON) >/dev/null

configure-app: deps-demo
	cmake --preset $(PRESET) -DTERRALOD_BUILD_TESTS=OFF -DTERRALOD_BUILD_BENCH=OFF >/dev/null

build: configure
	cmake --build --preset $(PRESET) -j $(JOBS)

# Only the programs (and the libraries they link), not the tests: terralod, what the demo runs,
# and terralod-stage beside it, which a cluster build's tasks that read no raster run.
app: configure-app
	cmake --build --preset $(PRESET) -j $(JOBS) --target terralod terralod-stage

demo: app
	mkdir -p $(DEMO_DIR)
	$(TERRALOD) build $(DEMO_DEM) --texture $(DEMO_IMAGE) -o $(DEMO_DIR)/zion.tlod
	$(TERRALOD) info $(DEMO_DIR)/zion.tlod
	$(TERRALOD) verify $(DEMO_DIR)/zion.tlod --source $(DEMO_DEM)
	$(TERRALOD) render $(DEMO_DIR)/zion.tlod -o $(DEMO_DIR)/zion.png
	mkdir -p $(DEMO_DIR)/flight
	$(TERRALOD) render $(DEMO_DIR)/zion.tlod --auto-flight --climb-only --every 30 --size 640x480 --frames-dir $(DEMO_DIR)/flight
	$(TERRALOD) bench $(DEMO_DIR)/zion.tlod --auto-flight --climb-only --frames 300 --size 640x480 --source $(DEMO_DEM) --json $(DEMO_DIR)/bench.json

test: build
	./scripts/check-format.sh
	ctest --preset $(PRESET)
	$(MAKE) test-tsan
	$(MAKE) test-sanitize

# The chunk loader and cache tests under ThreadSanitizer (a build of the runtime tests only).
test-tsan: deps
	cmake --preset tsan >/dev/null
	cmake --build --preset tsan -j $(JOBS)
	ctest --preset tsan

# Everything that reads untrusted bytes, under sanitizers, from one clang build (preset fuzz,
# docs/reliability.md): the unit tests of core, format, runtime and raster under
# AddressSanitizer + UBSan, and every libFuzzer target for a few seconds over its seeds
# (bench/fuzz.sh runs them for longer).
test-sanitize: deps
	cmake --preset fuzz >/dev/null
	cmake --build --preset fuzz -j $(JOBS)
	ctest --preset fuzz

# The same unit tests in a plain ASan + UBSan build without fuzzing instrumentation (preset asan,
# which also builds the CLI for bench/leak_check.sh); not part of make test.
test-asan: deps
	cmake --preset asan >/dev/null
	cmake --build --preset asan -j $(JOBS)
	ctest --preset asan

format:
	./scripts/check-format.sh --fix

check-format:
	./scripts/check-format.sh

clean:
	rm -rf build
