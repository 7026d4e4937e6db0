# tridex: `make demo` and `make test` on a fresh Debian 12 machine (see README.md).
PRESET ?= release
BUILD  := build/$(PRESET)
JOBS   ?= $(shell nproc)
# Tests at once: one more than the cores, because many tests are sessions paced in real time (a 60 Hz display, a
# 1 kHz haptic loop) that leave a core partly idle. Timing-sensitive tests run alone (RUN_SERIAL, tests/CMakeLists.txt).
TEST_JOBS ?= $(shell expr $$(nproc) + 1)
# Extra cache settings for the configure step, e.g. CMAKE_ARGS=-DTRIDEX_WERROR=OFF (warnings are errors by default, as in CI).
CMAKE_ARGS ?=

.PHONY: all deps configure build demo test bench clean

all: build

# The install script checks each package and installs only what is missing (fast when none is).
deps:
	bash scripts/install-deps.sh

configure: deps
	cmake --preset $(PRESET) $(CMAKE_ARGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The demo needs only the `tridex` binary (and the libraries it links), not the test programs.
demo: configure
	cmake --build $(BUILD) -j $(JOBS) --target tridex
	$(BUILD)/app/tridex demo

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(TEST_JOBS)

# Benchmarks print tables and write JSON under out/bench (numbers for notes, not pass/fail).
bench: build
	$(BUILD)/app/tridex bench --haptics --render --sculpt --session --accuracy --out out/bench

clean:
	rm -rf build out
