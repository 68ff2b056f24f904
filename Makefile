# The two Quick-start commands. Both install missing Debian packages, configure and build
# Release out of tree (build/), then run.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: demo test build deps asan fuzz bench format clean

deps:
	@scripts/install-deps

build: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(BUILD)/hil/mirage demo
	scripts/demo-stream $(BUILD)

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -LE 'bench|asan'
	cd $(BUILD) && ctest --output-on-failure -L bench

# Unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (generic x86-64 code: g++ 12's
# -O2 inlining of Eigen's AVX-512 paths raises a false maybe-uninitialized warning).
asan: deps
	cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMIRAGE_SANITIZE=ON -DMIRAGE_NATIVE=OFF $(CMAKE_FLAGS)
	cmake --build build-asan -j $(JOBS)
	cd build-asan && ctest --output-on-failure -j $(JOBS) -L unit

# libFuzzer (Clang) on the packet and navigation decoders under ASan+UBSan, FUZZ_SECONDS each, with a corpus
# kept in build-fuzz/corpus.
FUZZ_SECONDS ?= 30
FUZZ_TARGETS = fuzz_velodyne_decode fuzz_ouster_decode fuzz_nmea fuzz_novatel fuzz_ncom \
               fuzz_navcan fuzz_slcan_bus fuzz_gsusb
fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)
	cmake --build build-fuzz -j $(JOBS) --target $(FUZZ_TARGETS)
	FUZZ_TARGETS="$(FUZZ_TARGETS)" scripts/run-fuzz build-fuzz $(FUZZ_SECONDS)

bench: build
	$(BUILD)/hil/mirage bench

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) build-asan build-fuzz
