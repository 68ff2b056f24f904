// SPDX-License-Identifier: Apache-2.0
// Walks the record headers of a classic pcap file (24-byte file header, then 16-byte record
// headers whose incl_len gives the record length) and truncates after the last complete one.
#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "mirage/core/error.hpp"
#include "mirage/pcap/writer.hpp"

namespace mirage::pcap {
namespace {

std::uint32_t le32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
           (std::uint32_t{p[3]} << 24);
}
std::uint32_t be32(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
           std::uint32_t{p[3]};
}

}  // namespace

std::uint64_t cut_to_whole_records(const std::string& path) {
    auto fail = [&](const std::string& why) {
        return IoError(fmt::format("pcap repair '{}': {}", path, why));
    };
    FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) throw fail(std::strerror(errno));
    std::array<std::uint8_t, 24> head{};
    const bool got_head = std::fread(head.data(), 1, head.size(), f) == head.size();
    const std::uint32_t magic = le32(head.data());
    bool little = true;
    if (magic == 0xa1b2c3d4u || magic == 0xa1b23c4du) {
        little = true;
    } else if (magic == 0xd4c3b2a1u || magic == 0x4d3cb2a1u) {
        little = false;
    } else {
        std::fclose(f);
        throw fail(got_head ? "not a classic pcap file" : "shorter than a pcap file header");
    }
    std::uint64_t good = head.size();
    std::array<std::uint8_t, 16> rec{};
    while (std::fread(rec.data(), 1, rec.size(), f) == rec.size()) {
        const std::uint32_t incl = little ? le32(&rec[8]) : be32(&rec[8]);
        if (incl > (256u << 20)) break;  // a lying header: cut here
        if (std::fseek(f, static_cast<long>(incl), SEEK_CUR) != 0) break;
        // fseek past the end succeeds; the file size tells whether the body is all there.
        const long pos = std::ftell(f);
        if (pos < 0) break;
        std::uint8_t probe = 0;
        if (incl > 0) {
            if (std::fseek(f, -1, SEEK_CUR) != 0 || std::fread(&probe, 1, 1, f) != 1) break;
        }
        good = static_cast<std::uint64_t>(pos);
    }
    std::fclose(f);
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) != good) {
        std::filesystem::resize_file(path, good, ec);
        if (ec) throw fail("cannot truncate: " + ec.message());
    }
    return good;
}

}  // namespace mirage::pcap
