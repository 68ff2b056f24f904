// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <numeric>

#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"
#include "raw_pcap.hpp"
#include "read_all.hpp"
#include "test_paths.hpp"

namespace {

using mirage::pcap::FrameStatus;
using mirage::pcap::Reader;
using mirage::pcap::UdpDatagram;
using namespace mirage::test;

constexpr std::uint32_t kLinuxSll = 113;

std::uint64_t total(const Reader& r) {
    return std::accumulate(r.counts().begin(), r.counts().end(), std::uint64_t{0});
}

Bytes udp_frame(const Bytes& payload, std::uint16_t dst_port = 2368) {
    return ethernet(0x0800, ipv4(17, udp(2368, dst_port, payload)));
}

// ---- real captures (../shared/captures) ----

TEST(PcapCapture, vlp16_has_84_data_packets_of_1206_bytes) {
    MIRAGE_CAPTURE_OR_SKIP(path, "vlp16_example.pcap");
    Reader r(path.string());
    const auto all = read_all(r);
    ASSERT_EQ(all.size(), 84u);
    EXPECT_EQ(r.count(FrameStatus::Ok), 84u);
    EXPECT_EQ(total(r), 84u);
    for (const auto& d : all) {
        EXPECT_EQ(d.payload.size(), 1206u);
        EXPECT_EQ(d.dst.port, 2368);
        EXPECT_EQ(d.payload[1204], 0x37);  // strongest return
        EXPECT_EQ(d.payload[1205], 0x22);  // VLP-16
    }
    EXPECT_EQ(all.front().src.ip, (std::array<std::uint8_t, 4>{192, 168, 1, 200}));
    EXPECT_EQ(all.front().src.port, 2368);
    // µs file read at ns precision: exact scaling.
    EXPECT_EQ(all.front().time_ns, 1525347606'362040000);
    EXPECT_EQ(all.back().time_ns, 1525347606'472382000);
    EXPECT_TRUE(r.error().empty());
}

TEST(PcapCapture, hdl32e_has_876_data_and_100_position_packets) {
    MIRAGE_CAPTURE_OR_SKIP(path, "hdl32e_with_position.pcap");
    const auto data = mirage::pcap::read_udp(path.string(), 2368);
    const auto pos = mirage::pcap::read_udp(path.string(), 8308);
    ASSERT_EQ(data.size(), 876u);
    ASSERT_EQ(pos.size(), 100u);
    for (const auto& d : data) {
        EXPECT_EQ(d.payload.size(), 1206u);
        EXPECT_EQ(d.payload[1205], 0x21);  // HDL-32E
    }
    for (const auto& d : pos) EXPECT_EQ(d.payload.size(), 512u);
    EXPECT_EQ(mirage::pcap::read_udp(path.string()).size(), 976u);
}

TEST(PcapCapture, os1_64_legacy_has_100_lidar_packets_of_12608_bytes) {
    MIRAGE_CAPTURE_OR_SKIP(path, "os1_64_legacy.pcap");
    const auto v = mirage::pcap::read_udp(path.string(), 7502);
    ASSERT_EQ(v.size(), 100u);
    for (const auto& d : v) EXPECT_EQ(d.payload.size(), 12608u);
    EXPECT_EQ(v.front().time_ns, 1561675844'795833000);
}

TEST(PcapCapture, os2_128_has_64_lidar_and_10_imu_packets) {
    MIRAGE_CAPTURE_OR_SKIP(path, "os2_128_rng19.pcap");
    const auto lidar = mirage::pcap::read_udp(path.string(), 7502);
    const auto imu = mirage::pcap::read_udp(path.string(), 7503);
    ASSERT_EQ(lidar.size(), 64u);
    ASSERT_EQ(imu.size(), 10u);
    for (const auto& d : lidar) EXPECT_EQ(d.payload.size(), 24832u);
    for (const auto& d : imu) EXPECT_EQ(d.payload.size(), 48u);
}

// ---- hand-built frames ----

TEST(PcapReader, reads_fields_and_nanosecond_time_of_one_ethernet_frame) {
    TempDir dir;
    const auto payload = pattern(1206);
    write_raw_pcap(dir.file("a.pcap"), kEthernet, {{1700000000'123456789, udp_frame(payload)}});
    Reader r(dir.file("a.pcap"));
    UdpDatagram d;
    ASSERT_TRUE(r.next(d));
    EXPECT_EQ(d.time_ns, 1700000000'123456789);
    EXPECT_EQ(d.src.ip, (std::array<std::uint8_t, 4>{192, 168, 1, 201}));
    EXPECT_EQ(d.dst.ip, (std::array<std::uint8_t, 4>{192, 168, 1, 77}));
    EXPECT_EQ(d.src.port, 2368);
    EXPECT_EQ(d.dst.port, 2368);
    EXPECT_EQ(d.payload, payload);
    EXPECT_FALSE(r.next(d));
    EXPECT_FALSE(r.next(d));  // stays at the end
    EXPECT_EQ(r.count(FrameStatus::Ok), 1u);
}

TEST(PcapReader, reads_vlan_tagged_and_linux_sll_frames) {
    TempDir dir;
    const auto payload = pattern(100);
    Bytes tagged = ethernet(0x8100, {});
    const Bytes tag = {0x00, 0x05, 0x08, 0x00};  // VLAN 5, inner type IPv4
    append(tagged, tag);
    const Bytes ip = ipv4(17, udp(1, 7502, payload));
    append(tagged, ip);
    write_raw_pcap(dir.file("vlan.pcap"), kEthernet, {{1, tagged}});
    auto v = mirage::pcap::read_udp(dir.file("vlan.pcap"));
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].dst.port, 7502);
    EXPECT_EQ(v[0].payload, payload);

    Bytes sll(16, 0);
    sll[14] = 0x08;  // protocol IPv4
    append(sll, ip);
    write_raw_pcap(dir.file("sll.pcap"), kLinuxSll, {{2, sll}});
    v = mirage::pcap::read_udp(dir.file("sll.pcap"));
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].payload, payload);
}

TEST(PcapReader, ignores_ethernet_padding_after_the_ip_packet) {
    TempDir dir;
    Bytes f = udp_frame({0xab});
    f.resize(60, 0xee);  // minimum Ethernet frame
    write_raw_pcap(dir.file("pad.pcap"), kEthernet, {{1, f}});
    const auto v = mirage::pcap::read_udp(dir.file("pad.pcap"));
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].payload, Bytes{0xab});
}

TEST(PcapReader, counts_every_frame_status_and_never_throws) {
    TempDir dir;
    std::vector<RawRecord> recs;
    const Bytes good = udp_frame(pattern(50));
    recs.push_back({1, good});
    Bytes cut = good;  // snaplen cut mid-UDP payload
    cut.resize(30);
    recs.push_back({2, cut, static_cast<std::uint32_t>(good.size())});
    recs.push_back({3, ethernet(0x0806, Bytes(28, 0))});  // ARP
    recs.push_back({4, ethernet(0x86dd, Bytes(48, 0))});  // IPv6 type, version 0: bad header
    recs.push_back({5, ethernet(0x0800, ipv4(6, Bytes(20, 0)))});                 // TCP
    recs.push_back({6, ethernet(0x0800, ipv4(17, udp(1, 2, {1, 2}), 1, 0, 4))});  // IHL 4
    recs.push_back({7, ethernet(0x0800, ipv4(17, udp(1, 2, {1, 2}, 200)))});      // UDP len > IP
    recs.push_back({8, ethernet(0x0800, ipv4(17, udp(1, 2, {1}), 1, 0x4000, 5, 300))});  // IP len
    recs.push_back({9, ethernet(0x0800, ipv4(17, Bytes(64, 0), 77, 0x2000))});  // lone fragment
    recs.push_back({10, Bytes(10, 0)});                                         // runt frame
    recs.push_back({11, good});
    write_raw_pcap(dir.file("mixed.pcap"), kEthernet, recs);

    Reader r(dir.file("mixed.pcap"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[0].time_ns, 1);
    EXPECT_EQ(v[1].time_ns, 11);
    EXPECT_EQ(r.count(FrameStatus::Ok), 2u);
    EXPECT_EQ(r.count(FrameStatus::Truncated), 1u);
    EXPECT_EQ(r.count(FrameStatus::NotIpv4), 1u);
    EXPECT_EQ(r.count(FrameStatus::NotUdp), 1u);
    EXPECT_EQ(r.count(FrameStatus::BadHeader), 5u);  // v6 0, IHL, UDP len, IP len, runt
    EXPECT_EQ(r.count(FrameStatus::Fragment), 1u);
    EXPECT_EQ(total(r), recs.size());
}

// Three pieces of one 3000-byte datagram, out of order, interleaved with another datagram.
TEST(PcapReader, reassembles_ip_fragments_in_any_order) {
    TempDir dir;
    const auto payload = pattern(3000 - 8);
    const Bytes whole = udp(2368, 7502, payload);  // 3000 bytes of IP payload
    auto piece = [&](std::size_t begin, std::size_t end, bool more) {
        const Bytes body(whole.begin() + static_cast<std::ptrdiff_t>(begin),
                         whole.begin() + static_cast<std::ptrdiff_t>(end));
        const auto fo = static_cast<std::uint16_t>((more ? 0x2000 : 0) | (begin / 8));
        return ethernet(0x0800, ipv4(17, body, 4242, fo));
    };
    write_raw_pcap(dir.file("frag.pcap"), kEthernet,
                   {{100, piece(1480, 2960, true)},
                    {200, udp_frame({9, 9})},
                    {300, piece(2960, 3000, false)},
                    {400, piece(0, 1480, true)}});
    Reader r(dir.file("frag.pcap"));
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[0].payload, (Bytes{9, 9}));
    EXPECT_EQ(v[1].dst.port, 7502);
    EXPECT_EQ(v[1].payload, payload);
    EXPECT_EQ(v[1].time_ns, 400);  // delivered when the last piece arrives
    EXPECT_EQ(r.count(FrameStatus::Ok), 4u);
    EXPECT_EQ(r.count(FrameStatus::Fragment), 0u);
}

TEST(PcapReader, gives_up_a_fragment_after_30_seconds_of_capture_time) {
    TempDir dir;
    write_raw_pcap(dir.file("old.pcap"), kEthernet,
                   {{0, ethernet(0x0800, ipv4(17, Bytes(64, 0), 5, 0x2000))},
                    {31'000'000'000, udp_frame({1})}});
    Reader r(dir.file("old.pcap"));
    UdpDatagram d;
    ASSERT_TRUE(r.next(d));
    EXPECT_EQ(r.count(FrameStatus::Fragment), 1u);  // already counted, before the end of file
}

TEST(PcapReader, stops_cleanly_at_a_record_cut_mid_way) {
    TempDir dir;
    const auto file = dir.file("cut.pcap");
    write_raw_pcap(file, kEthernet, {{1, udp_frame(pattern(500))}, {2, udp_frame(pattern(500))}});
    std::filesystem::resize_file(file, std::filesystem::file_size(file) - 100);
    Reader r(file);
    const auto v = read_all(r);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].payload, pattern(500));
    EXPECT_EQ(r.count(FrameStatus::Truncated), 1u);
    EXPECT_FALSE(r.error().empty());
}

TEST(PcapReader, throws_io_error_naming_a_missing_or_foreign_file) {
    TempDir dir;
    const auto missing = dir.file("missing.pcap");
    try {
        Reader r(missing);
        FAIL() << "no exception";
    } catch (const mirage::IoError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
    write_raw_pcap(dir.file("wifi.pcap"), 105, {});  // IEEE 802.11
    EXPECT_THROW(Reader r(dir.file("wifi.pcap")), mirage::IoError);
}

}  // namespace
