// SPDX-License-Identifier: Apache-2.0
#pragma once
// Hand-built frames and classic pcap files for reader tests, written byte by byte so that the
// reader is checked against an encoder that shares no code with it.
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace mirage::test {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint32_t kEthernet = 1;  // LINKTYPE_ETHERNET, for write_raw_pcap

inline void put16(Bytes& b, std::size_t at, unsigned v) {
    b[at] = static_cast<std::uint8_t>(v >> 8);
    b[at + 1] = static_cast<std::uint8_t>(v);
}

// Appends byte by byte (GCC 12 reports a false -Warray-bounds on vector::insert here).
inline void append(Bytes& a, const Bytes& b) {
    a.reserve(a.size() + b.size());
    for (const auto x : b) a.push_back(x);
}

inline Bytes ethernet(std::uint16_t ethertype, const Bytes& body) {
    Bytes f = {0x60, 0x76, 0x88, 0x00, 0x00, 0x00, 0x00, 0x1b, 0x21, 0x00, 0x00, 0x01, 0, 0};
    put16(f, 12, ethertype);
    append(f, body);
    return f;
}

// IPv4 header (IHL 5 unless `ihl` given) + body; flags_offset is the raw 16-bit field.
inline Bytes ipv4(std::uint8_t proto, const Bytes& body, std::uint16_t id = 1,
                  std::uint16_t flags_offset = 0x4000, unsigned ihl = 5, int total = -1) {
    Bytes h(20, 0);
    h[0] = static_cast<std::uint8_t>(0x40 | ihl);
    put16(h, 2,
          total >= 0 ? static_cast<unsigned>(total) : static_cast<unsigned>(20 + body.size()));
    put16(h, 4, id);
    put16(h, 6, flags_offset);
    h[8] = 64;
    h[9] = proto;
    const std::uint8_t src[4] = {192, 168, 1, 201}, dst[4] = {192, 168, 1, 77};
    for (int i = 0; i < 4; ++i) {
        h[12 + static_cast<std::size_t>(i)] = src[i];
        h[16 + static_cast<std::size_t>(i)] = dst[i];
    }
    append(h, body);
    return h;
}

inline Bytes udp(std::uint16_t src_port, std::uint16_t dst_port, const Bytes& payload,
                 int length = -1) {
    Bytes u(8, 0);
    put16(u, 0, src_port);
    put16(u, 2, dst_port);
    put16(u, 4,
          length >= 0 ? static_cast<unsigned>(length) : static_cast<unsigned>(8 + payload.size()));
    append(u, payload);
    return u;
}

inline Bytes pattern(std::size_t n, unsigned seed = 7) {
    Bytes p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>((i * 31 + seed) >> 1);
    return p;
}

struct RawRecord {
    std::int64_t time_ns = 0;
    Bytes frame;
    std::uint32_t orig_len = 0;  // 0: frame.size()
};

// Classic little-endian pcap with nanosecond magic (a1b23c4d).
inline void write_raw_pcap(const std::string& path, std::uint32_t linktype,
                           const std::vector<RawRecord>& records) {
    std::ofstream out(path, std::ios::binary);
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) out.put(static_cast<char>((v >> (8 * i)) & 0xff));
    };
    auto u16 = [&](std::uint16_t v) {
        out.put(static_cast<char>(v & 0xff));
        out.put(static_cast<char>(v >> 8));
    };
    u32(0xa1b23c4d);
    u16(2);
    u16(4);
    u32(0);
    u32(0);
    u32(262144);
    u32(linktype);
    for (const auto& r : records) {
        u32(static_cast<std::uint32_t>(r.time_ns / 1'000'000'000));
        u32(static_cast<std::uint32_t>(r.time_ns % 1'000'000'000));
        u32(static_cast<std::uint32_t>(r.frame.size()));
        u32(r.orig_len ? r.orig_len : static_cast<std::uint32_t>(r.frame.size()));
        out.write(reinterpret_cast<const char*>(r.frame.data()),
                  static_cast<std::streamsize>(r.frame.size()));
    }
}

// Reads back a classic little-endian pcap (either magic) record by record; stops at a cut record.
struct RawFile {
    std::uint32_t magic = 0;
    std::uint32_t linktype = 0;
    std::vector<RawRecord> records;
};
inline RawFile read_raw_pcap(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const Bytes b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto u32 = [&](std::size_t at) {
        return std::uint32_t{b[at]} | (std::uint32_t{b[at + 1]} << 8) |
               (std::uint32_t{b[at + 2]} << 16) | (std::uint32_t{b[at + 3]} << 24);
    };
    RawFile f;
    if (b.size() < 24) return f;
    f.magic = u32(0);
    f.linktype = u32(20);
    const std::int64_t sub = f.magic == 0xa1b23c4d ? 1 : 1000;
    for (std::size_t at = 24; at + 16 <= b.size();) {
        const std::uint32_t caplen = u32(at + 8);
        if (at + 16 + caplen > b.size()) break;
        RawRecord r;
        r.time_ns = std::int64_t{u32(at)} * 1'000'000'000 + std::int64_t{u32(at + 4)} * sub;
        r.orig_len = u32(at + 12);
        r.frame.assign(b.begin() + static_cast<std::ptrdiff_t>(at + 16),
                       b.begin() + static_cast<std::ptrdiff_t>(at + 16 + caplen));
        f.records.push_back(std::move(r));
        at += 16 + caplen;
    }
    return f;
}

// RFC 1071 sum over 16-bit big-endian words, folded (0xffff for a valid checksummed block).
inline std::uint32_t ones_complement_sum(const std::uint8_t* p, std::size_t n,
                                         std::uint32_t s = 0) {
    for (std::size_t i = 0; i < n; ++i) s += (i % 2 == 0) ? std::uint32_t{p[i]} << 8 : p[i];
    while (s >> 16) s = (s & 0xffff) + (s >> 16);
    return s;
}

}  // namespace mirage::test
