# The two Quick-start commands. Both install missing Debian packages, configure and build
# Release out of tree (build/), then run.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: demo test build deps asan fuzz fuzz-seeds bench format clean

deps:
	@scripts/install-deps

build: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)
	@scripts/install-peers $(BUILD)

demo: build
	$(BUILD)/hil/mirage demo
	scripts/demo-stream $(BUILD)

# A test that sets no TIMEOUT of its own fails after TEST_TIMEOUT seconds instead of holding CI
# until its own deadline (the slowest takes under 20 s, 40 s sanitized; docs/testing.md §2).
TEST_TIMEOUT ?= 600
CTEST = ctest --output-on-failure --timeout $(TEST_TIMEOUT)

test: build
	cd $(BUILD) && $(CTEST) -j $(JOBS) -LE 'bench|asan'
	cd $(BUILD) && $(CTEST) -L bench

# Unit and loopback tests under AddressSanitizer + UndefinedBehaviorSanitizer (generic x86-64 code:
# g++ 12's -O2 inlining of Eigen's AVX-512 paths raises a false maybe-uninitialized warning).
# Line tables only (-g1): sanitizer reports keep function, file and line. -O1, not -O2: the build
# is the longest step of CI and UBSan's checks make g++'s -O2 pass about twice as slow (a heavy
# test file compiles in about half the time at -O1); docs/testing.md.
asan: deps
	cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DMIRAGE_SANITIZE=ON -DMIRAGE_NATIVE=OFF $(CMAKE_FLAGS)
	cmake --build build-asan -j $(JOBS)
	@scripts/install-peers build-asan
	cd build-asan && $(CTEST) -j $(JOBS) -L 'unit|loopback'

# libFuzzer (Clang) under ASan+UBSan on every parser of outside bytes: only the fuzz targets and
# the libraries they link are built (coverage-instrumented, -DMIRAGE_FUZZ=ON); each runs
# FUZZ_SECONDS from its committed seed corpus (scripts/run-fuzz; table in build-fuzz/fuzz-report.md).
FUZZ_SECONDS ?= 30
fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMIRAGE_FUZZ=ON $(CMAKE_FLAGS)
	cmake --build build-fuzz -j $(JOBS) --target mirage_fuzz
	scripts/run-fuzz build-fuzz $(FUZZ_SECONDS)

# Rewrites the generated fuzz seeds (gen_*) in the source tree from Mirage's encoders.
fuzz-seeds: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS) --target mirage_fuzz_seed_gen
	$(BUILD)/tests/mirage_fuzz_seed_gen .

bench: build
	$(BUILD)/hil/mirage bench

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) build-asan build-fuzz
