// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/bytestream/byte_stream.hpp"

namespace mirage::bytestream::test {

inline std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// Reads until `want` bytes arrived, the stream reports Closed, or `budget` is spent.
inline std::string read_exactly(ByteStream& s, std::size_t want,
                                std::chrono::milliseconds budget = std::chrono::seconds(5)) {
    std::string out;
    std::vector<std::uint8_t> buf(4096);
    const auto end = std::chrono::steady_clock::now() + budget;
    while (out.size() < want && std::chrono::steady_clock::now() < end) {
        std::size_t n = 0;
        std::int64_t host_ns = 0;
        const auto st = s.read(buf, n, host_ns, std::chrono::milliseconds(200));
        if (st == ReadStatus::Data) out.append(reinterpret_cast<const char*>(buf.data()), n);
    }
    return out;
}

}  // namespace mirage::bytestream::test
