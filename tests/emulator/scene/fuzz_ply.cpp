// SPDX-License-Identifier: Apache-2.0
// libFuzzer: Stanford PLY (ascii, binary little- and big-endian). Bad content must end in
// ConfigError; a returned mesh must be consistent (fuzz_mesh.hpp).
#include <cstddef>
#include <cstdint>

#include "fuzz_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mirage::scene::test::fuzz_mesh_reader(mirage::scene::parse_ply, data, size);
    return 0;
}
