// SPDX-License-Identifier: Apache-2.0
// libFuzzer target (Clang): clang++ -fsanitize=fuzzer,address,undefined. Both decoders must
// return a status for any input without reading out of bounds.
#include <cstddef>
#include <cstdint>

#include "fuzz_decode_one.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mirage::velodyne::test::FuzzCounters c;
    mirage::velodyne::test::fuzz_one({data, size}, c);
    mirage::velodyne::test::fuzz_structured({data, size}, c);
    return 0;
}
