// SPDX-License-Identifier: Apache-2.0
// Reader extensions for issue 5: IPv6, pcapng, BPF filters, error byte offsets, unknown link
// types counted, and cutting a damaged file to its whole records.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>

#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/pcap/writer.hpp"
#include "raw_pcap.hpp"
#include "read_all.hpp"
#include "test_paths.hpp"

namespace {

using mirage::pcap::FrameStatus;
using mirage::pcap::Reader;
using mirage::pcap::UdpDatagram;
using namespace mirage::test;

Bytes ipv6(std::uint8_t next, const Bytes& body, std::uint8_t src_last = 1) {
    Bytes h(40, 0);
    h[0] = 0x60;
    put16(h, 4, static_cast<unsigned>(body.size()));
    h[6] = next;
    h[7] = 64;
    h[8] = 0x20;  // 2001:db8::src_last -> 2001:db8::2
    h[9] = 0x01;
    h[10] = 0x0d;
    h[11] = 0xb8;
    h[23] = src_last;
    h[24] = 0x20;
    h[25] = 0x01;
    h[26] = 0x0d;
    h[27] = 0xb8;
    h[39] = 2;
    append(h, body);
    return h;
}

TEST(PcapReaderExt, reads_ipv6_udp_with_and_without_extension_headers) {
    TempDir dir;
    // Hop-by-hop options header (8 bytes) then UDP.
    Bytes hop = {17, 0, 0, 0, 0, 0, 0, 0};
    append(hop, udp(2368, 2369, {4, 5, 6}));
    // A real (non-atomic) fragment header: offset 0, M = 1.
    Bytes frag = {17, 0, 0x00, 0x01, 0, 0, 0, 9};
    append(frag, udp(1, 2, pattern(16)));
    write_raw_pcap(dir.file("v6.pcap"), kEthernet,
                   {{10, ethernet(0x86dd, ipv6(17, udp(2368, 2368, {1, 2, 3})))},
                    {20, ethernet(0x86dd, ipv6(0, hop))},
                    {30, ethernet(0x86dd, ipv6(44, frag))},
                    {40, ethernet(0x86dd, ipv6(6, Bytes(20, 0)))}});
    Reader r(dir.file("v6.pcap"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_TRUE(v[0].src.v6);
    EXPECT_EQ(v[0].src.ip6[0], 0x20);
    EXPECT_EQ(v[0].src.ip6[15], 1);
    EXPECT_EQ(v[0].dst.ip6[15], 2);
    EXPECT_EQ(v[0].src.ip, (std::array<std::uint8_t, 4>{0, 0, 0, 0}));
    EXPECT_EQ(v[0].payload, (Bytes{1, 2, 3}));
    EXPECT_EQ(v[1].dst.port, 2369);
    EXPECT_EQ(v[1].payload, (Bytes{4, 5, 6}));
    EXPECT_EQ(r.count(FrameStatus::Fragment), 1u);  // a first piece whose rest never came
    EXPECT_EQ(r.count(FrameStatus::NotUdp), 1u);
}

// IPv6 fragments (RFC 8200 §4.5) of one 3000-byte UDP datagram, behind a hop-by-hop header,
// arriving last piece first with an overlapping duplicate; a second datagram from another
// source reuses the identification and never completes.
std::vector<RawRecord> ipv6_fragments(const Bytes& whole) {
    auto piece = [&](std::size_t begin, std::size_t end, bool more, std::uint8_t src_last) {
        Bytes body = {44, 0, 0, 0, 0, 0, 0, 0};  // hop-by-hop, next header: fragment
        const auto fo = static_cast<unsigned>(begin | (more ? 1u : 0u));
        Bytes frag = {17,
                      0,
                      static_cast<std::uint8_t>(fo >> 8),
                      static_cast<std::uint8_t>(fo),
                      0xca,
                      0xfe,
                      0xba,
                      0xbe};
        append(body, frag);
        append(body, Bytes(whole.begin() + static_cast<std::ptrdiff_t>(begin),
                           whole.begin() + static_cast<std::ptrdiff_t>(end)));
        return ethernet(0x86dd, ipv6(0, body, src_last));
    };
    return {{1, piece(2400, 3000, false, 1)},
            {2, piece(1200, 2400, true, 1)},
            {3, piece(0, 1208, true, 7)},  // other source: its own datagram
            {4, piece(0, 1208, true, 1)},
            {5, piece(1200, 1208, true, 1)}};  // duplicate of bytes already there
}

TEST(PcapReaderExt, reassembles_ipv6_fragments_in_any_order) {
    TempDir dir;
    const auto payload = pattern(3000 - 8);
    write_raw_pcap(dir.file("v6f.pcap"), kEthernet, ipv6_fragments(udp(7502, 7503, payload)));
    Reader r(dir.file("v6f.pcap"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_TRUE(v[0].dst.v6);
    EXPECT_EQ(v[0].src.ip6[15], 1);
    EXPECT_EQ(v[0].src.port, 7502);
    EXPECT_EQ(v[0].dst.port, 7503);
    EXPECT_EQ(v[0].payload, payload);
    EXPECT_EQ(v[0].time_ns, 4);                     // when the datagram became whole
    EXPECT_EQ(r.count(FrameStatus::Ok), 3u);        // the three pieces that completed it
    EXPECT_EQ(r.count(FrameStatus::Fragment), 2u);  // the other source's piece, the duplicate
}

TEST(PcapReaderExt, filter_judges_a_reassembled_ipv6_datagram_as_a_whole) {
    TempDir dir;
    write_raw_pcap(dir.file("v6f.pcap"), kEthernet,
                   ipv6_fragments(udp(7502, 7503, pattern(3000 - 8))));
    Reader a(dir.file("v6f.pcap"));
    a.set_filter("ip6 and udp dst port 7503 and src host 2001:db8::1");
    EXPECT_EQ(read_all(a).size(), 1u);
    Reader b(dir.file("v6f.pcap"));
    b.set_filter("udp port 2368");
    EXPECT_EQ(read_all(b).size(), 0u);
    EXPECT_EQ(b.filtered(), 3u);  // the whole datagram's three pieces
}

TEST(PcapReaderExt, reads_double_tagged_vlan_frames) {
    TempDir dir;
    Bytes f = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0x88, 0xa8, 0, 5, 0x81, 0x00, 0, 7, 0x08, 0};
    append(f, ipv4(17, udp(2368, 2368, {7, 7})));
    write_raw_pcap(dir.file("qinq.pcap"), kEthernet, {{5, f}});
    Reader r(dir.file("qinq.pcap"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].payload, (Bytes{7, 7}));
}

// Minimal pcapng (little endian): SHB, IDB (Ethernet, if_tsresol 9 = ns), EPBs.
void write_pcapng(const std::string& path, const std::vector<RawRecord>& recs) {
    Bytes b;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    };
    auto u16 = [&](std::uint16_t v) {
        b.push_back(static_cast<std::uint8_t>(v));
        b.push_back(static_cast<std::uint8_t>(v >> 8));
    };
    u32(0x0a0d0d0a);  // SHB
    u32(28);
    u32(0x1a2b3c4d);
    u16(1);
    u16(0);
    u32(0xffffffff);
    u32(0xffffffff);  // section length -1
    u32(28);
    u32(1);  // IDB with option if_tsresol = 9
    u32(32);
    u16(1);
    u16(0);
    u32(262144);
    u16(9);
    u16(1);
    b.insert(b.end(), {9, 0, 0, 0});
    u16(0);
    u16(0);
    u32(32);
    for (const auto& r : recs) {
        const auto padded = (r.frame.size() + 3) / 4 * 4;
        const auto len = static_cast<std::uint32_t>(32 + padded);
        u32(6);
        u32(len);
        u32(0);
        const auto t = static_cast<std::uint64_t>(r.time_ns);
        u32(static_cast<std::uint32_t>(t >> 32));
        u32(static_cast<std::uint32_t>(t));
        u32(static_cast<std::uint32_t>(r.frame.size()));
        u32(static_cast<std::uint32_t>(r.frame.size()));
        append(b, r.frame);
        b.resize(b.size() + padded - r.frame.size(), 0);
        u32(len);
    }
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

TEST(PcapReaderExt, reads_pcapng_with_nanosecond_timestamps) {
    TempDir dir;
    const auto f1 = ethernet(0x0800, ipv4(17, udp(2368, 2368, pattern(100))));
    const auto f2 = ethernet(0x0800, ipv4(17, udp(8308, 8308, pattern(50, 3))));
    write_pcapng(dir.file("a.pcapng"),
                 {{1'700'000'000'123'456'789, f1}, {1'700'000'001'000'000'001, f2}});
    Reader r(dir.file("a.pcapng"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 2u) << r.error();
    EXPECT_EQ(v[0].time_ns, 1'700'000'000'123'456'789);
    EXPECT_EQ(v[1].time_ns, 1'700'000'001'000'000'001);
    EXPECT_EQ(v[0].payload, pattern(100));
    EXPECT_EQ(v[1].dst.port, 8308);
    EXPECT_TRUE(r.error().empty());
}

// A 64-bit pcapng stamp past year 2262 has no int64 ns: the record counts as BadHeader and reading
// goes on (fuzz_pcap_reader found the overflow).
TEST(PcapReaderExt, timestamp_beyond_int64_ns_is_a_bad_record) {
    TempDir dir;
    const auto f = ethernet(0x0800, ipv4(17, udp(2368, 2368, pattern(20))));
    const std::int64_t far = static_cast<std::int64_t>(0xFFFF'FFFF'0000'0000ull);  // 1.8e19 ns
    write_pcapng(dir.file("far.pcapng"),
                 {{1'700'000'000'000'000'000, f}, {far, f}, {1'700'000'002'000'000'000, f}});
    Reader r(dir.file("far.pcapng"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 2u) << r.error();
    EXPECT_EQ(v[1].time_ns, 1'700'000'002'000'000'000);
    EXPECT_EQ(r.count(FrameStatus::BadHeader), 1u);
    EXPECT_EQ(r.count(FrameStatus::Ok), 2u);
}

TEST(PcapReaderExt, filter_expression_selects_ports_and_matches_every_fragment) {
    TempDir dir;
    const auto payload = pattern(3000 - 8);
    const Bytes whole = udp(7502, 7502, payload);
    auto piece = [&](std::size_t begin, std::size_t end, bool more) {
        const Bytes body(whole.begin() + static_cast<std::ptrdiff_t>(begin),
                         whole.begin() + static_cast<std::ptrdiff_t>(end));
        const auto fo = static_cast<std::uint16_t>((more ? 0x2000 : 0) | (begin / 8));
        return ethernet(0x0800, ipv4(17, body, 99, fo));
    };
    write_raw_pcap(dir.file("f.pcap"), kEthernet,
                   {{1, ethernet(0x0800, ipv4(17, udp(2368, 2368, {1})))},
                    {2, piece(0, 1480, true)},
                    {3, piece(1480, 2960, true)},
                    {4, piece(2960, 3000, false)},
                    {5, ethernet(0x0800, ipv4(17, udp(8308, 8308, {2})))}});
    Reader a(dir.file("f.pcap"));
    a.set_filter("udp dst port 7502");
    auto v = read_all(a);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].payload, payload);
    EXPECT_EQ(a.filtered(), 2u);
    EXPECT_EQ(a.count(FrameStatus::Ok), 3u);

    Reader b(dir.file("f.pcap"));
    b.set_filter("not port 7502");
    v = read_all(b);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[1].payload, (Bytes{2}));
    EXPECT_EQ(b.filtered(), 3u);  // the three fragments, as one datagram

    Reader c(dir.file("f.pcap"));
    try {
        c.set_filter("udp port banana");
        FAIL() << "no exception";
    } catch (const mirage::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("banana"), std::string::npos) << e.what();
    }
}

TEST(PcapReaderExt, error_names_the_byte_offset_of_the_damaged_record) {
    TempDir dir;
    const auto file = dir.file("cut.pcap");
    const auto frame = ethernet(0x0800, ipv4(17, udp(1, 2, pattern(200))));
    write_raw_pcap(file, kEthernet, {{1, frame}, {2, frame}, {3, frame}});
    const auto rec = 16 + frame.size();
    std::filesystem::resize_file(file, 24 + 2 * rec + 20);  // third record cut
    Reader r(file);
    UdpDatagram d;
    ASSERT_TRUE(r.next(d));
    EXPECT_EQ(r.record_offset(), 24);
    ASSERT_TRUE(r.next(d));
    EXPECT_EQ(r.record_offset(), static_cast<std::int64_t>(24 + rec));
    EXPECT_FALSE(r.next(d));
    EXPECT_EQ(r.error_offset(), static_cast<std::int64_t>(24 + 2 * rec));
    EXPECT_NE(r.error().find(std::to_string(24 + 2 * rec)), std::string::npos) << r.error();
    EXPECT_EQ(r.count(FrameStatus::Truncated), 1u);
}

TEST(PcapReaderExt, unknown_link_type_counts_every_frame_when_asked_not_to_throw) {
    TempDir dir;
    write_raw_pcap(dir.file("wifi.pcap"), 105, {{1, Bytes(40, 1)}, {2, Bytes(50, 2)}});
    Reader r(dir.file("wifi.pcap"), mirage::pcap::ReaderOptions{.unknown_link_throws = false});
    EXPECT_FALSE(r.link_supported());
    EXPECT_EQ(r.link_type(), 105);
    EXPECT_TRUE(read_all(r).empty());
    EXPECT_EQ(r.count(FrameStatus::NotIpv4), 2u);
}

TEST(PcapReaderExt, cut_to_whole_records_drops_only_the_partial_last_record) {
    TempDir dir;
    const auto file = dir.file("w.pcap");
    {
        mirage::pcap::Writer w(file);
        for (int i = 0; i < 5; ++i) w.write(i, {}, {{127, 0, 0, 1}, 9}, pattern(100));
    }
    const auto full = std::filesystem::file_size(file);
    EXPECT_EQ(mirage::pcap::cut_to_whole_records(file), full);  // nothing to cut
    const auto rec = (full - 24) / 5;
    std::filesystem::resize_file(file, full - 7);
    EXPECT_EQ(mirage::pcap::cut_to_whole_records(file), 24 + 4 * rec);
    EXPECT_EQ(std::filesystem::file_size(file), 24 + 4 * rec);
    Reader r(file);
    EXPECT_EQ(read_all(r).size(), 4u);
    EXPECT_TRUE(r.error().empty());
}

}  // namespace
