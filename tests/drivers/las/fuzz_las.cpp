// SPDX-License-Identifier: Apache-2.0
// libFuzzer: LAS file bytes through the reader and its validation. A corrupt file must be read
// without reading out of bounds; only whole records present in the file are decoded.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mirage/las/las_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<std::uint8_t> bytes(data, data + size);
    const auto f = mirage::las::LasFile::from_bytes(bytes);
    const auto problems = f.validate();
    if (f.file_size() != size || f.points().size() > f.records_in_file()) __builtin_trap();
    if (f.header().record_length != 0 && f.records_in_file() > size / f.header().record_length)
        __builtin_trap();
    (void)problems;
    return 0;
}
