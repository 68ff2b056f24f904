// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <numeric>

#include "mirage/core/error.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/pcap/writer.hpp"
#include "raw_pcap.hpp"
#include "test_paths.hpp"

namespace {

using mirage::pcap::Endpoint;
using mirage::pcap::FrameStatus;
using mirage::pcap::Reader;
using mirage::pcap::UdpDatagram;
using mirage::pcap::Writer;
using namespace mirage::test;

const Endpoint kSrc{{192, 168, 1, 201}, 2368};
const Endpoint kDst{{192, 168, 1, 77}, 2369};

std::uint16_t be16(const Bytes& b, std::size_t at) {
    return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

TEST(PcapWriter, round_trips_payload_sizes_up_to_65507_with_exact_ns_times) {
    TempDir dir;
    const std::vector<std::size_t> sizes = {0, 1, 1206, 12608, 65507};
    const std::int64_t t0 = 1'700'000'000'000'000'001;
    {
        Writer w(dir.file("rt.pcap"));
        for (std::size_t i = 0; i < sizes.size(); ++i)
            ASSERT_TRUE(w.write(t0 + static_cast<std::int64_t>(i) * 123'456'789, kSrc, kDst,
                                pattern(sizes[i], static_cast<unsigned>(i))));
        EXPECT_EQ(w.datagrams(), 5u);
        EXPECT_EQ(w.frames(), 1u + 1u + 1u + 9u + 45u);  // ceil((n + 8) / 1480) each
    }
    Reader r(dir.file("rt.pcap"));
    UdpDatagram d;
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        ASSERT_TRUE(r.next(d)) << i;
        EXPECT_EQ(d.time_ns, t0 + static_cast<std::int64_t>(i) * 123'456'789);
        EXPECT_EQ(d.payload, pattern(sizes[i], static_cast<unsigned>(i))) << sizes[i];
        EXPECT_EQ(d.src.ip, kSrc.ip);
        EXPECT_EQ(d.dst.ip, kDst.ip);
        EXPECT_EQ(d.src.port, 2368);
        EXPECT_EQ(d.dst.port, 2369);
    }
    EXPECT_FALSE(r.next(d));
    EXPECT_EQ(r.count(FrameStatus::Ok), 57u);
    EXPECT_EQ(std::accumulate(r.counts().begin(), r.counts().end(), std::uint64_t{0}), 57u);
}

TEST(PcapWriter, microsecond_files_truncate_times_to_the_microsecond) {
    TempDir dir;
    {
        Writer w(dir.file("us.pcap"), false);
        w.write(1'500'000'000'123'456'789, kSrc, kDst, pattern(10));
    }
    EXPECT_EQ(read_raw_pcap(dir.file("us.pcap")).magic, 0xa1b2c3d4u);
    const auto v = mirage::pcap::read_udp(dir.file("us.pcap"));
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].time_ns, 1'500'000'000'123'456'000);
}

// The frames a Linux host puts on a 1500-byte-MTU link, checked field by field.
TEST(PcapWriter, frames_and_fragments_like_a_linux_host_with_valid_checksums) {
    TempDir dir;
    const auto small = pattern(1206), big = pattern(12608);
    {
        Writer w(dir.file("f.pcap"));
        w.write(1, kSrc, kDst, small);
        w.write(2, kSrc, kDst, big);
    }
    const auto f = read_raw_pcap(dir.file("f.pcap"));
    EXPECT_EQ(f.magic, 0xa1b23c4du);
    EXPECT_EQ(f.linktype, 1u);
    ASSERT_EQ(f.records.size(), 10u);

    const Bytes& one = f.records[0].frame;
    ASSERT_EQ(one.size(), 1248u);  // Velodyne data frame on the wire (docs/wire-formats.md §1)
    EXPECT_EQ(be16(one, 12), 0x0800);
    EXPECT_EQ(one[14], 0x45);
    EXPECT_EQ(be16(one, 16), 1234);
    EXPECT_EQ(be16(one, 20), 0x4000);  // DF, offset 0
    EXPECT_EQ(one[23], 17);
    EXPECT_EQ(ones_complement_sum(&one[14], 20), 0xffffu);
    // UDP checksum over the pseudo-header verifies to 0xffff.
    std::uint32_t s = ones_complement_sum(&one[26], 8);  // src + dst IP
    s += 17 + be16(one, 38);
    s = ones_complement_sum(&one[34], one.size() - 34, s);
    EXPECT_EQ(s, 0xffffu);

    Bytes joined;
    const std::uint16_t id = be16(f.records[1].frame, 18);
    for (std::size_t k = 0; k < 9; ++k) {
        const Bytes& fr = f.records[1 + k].frame;
        const bool last = k == 8;
        EXPECT_EQ(fr.size(), last ? 14u + 20u + (12616u - 8u * 1480u) : 1514u) << k;
        EXPECT_EQ(be16(fr, 18), id);
        EXPECT_EQ(be16(fr, 20), (last ? 0 : 0x2000) | (k * 185)) << k;  // MF, offset / 8
        EXPECT_EQ(ones_complement_sum(&fr[14], 20), 0xffffu) << k;
        EXPECT_EQ(f.records[1 + k].time_ns, 2);
        joined.insert(joined.end(), fr.begin() + 34, fr.end());
    }
    ASSERT_EQ(joined.size(), 12616u);
    EXPECT_EQ(be16(joined, 4), 12616);  // UDP length in the first fragment
    EXPECT_TRUE(std::equal(big.begin(), big.end(), joined.begin() + 8));
    s = ones_complement_sum(&one[26], 8);
    s += 17 + 12616u;
    EXPECT_EQ(ones_complement_sum(joined.data(), joined.size(), s), 0xffffu);
}

TEST(PcapWriter, pads_short_frames_and_maps_broadcast_and_multicast_macs) {
    TempDir dir;
    {
        Writer w(dir.file("m.pcap"));
        w.write(1, kSrc, Endpoint{{255, 255, 255, 255}, 2368}, {});
        w.write(2, kSrc, Endpoint{{239, 129, 2, 3}, 2368}, pattern(4));
    }
    const auto f = read_raw_pcap(dir.file("m.pcap"));
    ASSERT_EQ(f.records.size(), 2u);
    EXPECT_EQ(f.records[0].frame.size(), 60u);
    EXPECT_EQ(Bytes(f.records[0].frame.begin(), f.records[0].frame.begin() + 6), Bytes(6, 0xff));
    EXPECT_EQ(Bytes(f.records[1].frame.begin(), f.records[1].frame.begin() + 6),
              (Bytes{0x01, 0x00, 0x5e, 0x01, 0x02, 0x03}));
    const auto v = mirage::pcap::read_udp(dir.file("m.pcap"));
    ASSERT_EQ(v.size(), 2u);
    EXPECT_TRUE(v[0].payload.empty());
    EXPECT_EQ(v[1].payload, pattern(4));
}

TEST(PcapWriter, rejects_payloads_over_65507_bytes_without_throwing) {
    TempDir dir;
    Writer w(dir.file("big.pcap"));
    EXPECT_FALSE(w.write(1, kSrc, kDst, Bytes(65508, 0)));
    EXPECT_TRUE(w.write(2, kSrc, kDst, Bytes(65507, 0)));
    EXPECT_EQ(w.rejected(), 1u);
    EXPECT_EQ(w.datagrams(), 1u);
}

TEST(PcapWriter, reports_a_full_disk_at_flush_naming_the_file) {
    if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "/dev/full not available";
    Writer w("/dev/full");
    for (int i = 0; i < 10; ++i) w.write(i, kSrc, kDst, pattern(1206));
    try {
        w.flush();
        FAIL() << "no exception";
    } catch (const mirage::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
        std::cout << "flush error: " << e.what() << "\n";
    }
    EXPECT_THROW(w.close(), mirage::IoError);
    EXPECT_NO_THROW(w.close());  // closed now; idempotent
}

TEST(PcapWriter, file_cut_mid_record_still_reads_every_whole_record) {
    TempDir dir;
    const auto file = dir.file("cut.pcap");
    {
        Writer w(file);
        for (int i = 0; i < 20; ++i)
            w.write(i * 1000, kSrc, kDst, pattern(1206, static_cast<unsigned>(i)));
        w.flush();  // on demand: everything is in the file before close
        EXPECT_EQ(std::filesystem::file_size(file), 24u + 20u * (16u + 1248u));
    }
    std::filesystem::resize_file(file, 24 + 12 * (16 + 1248) + 700);  // mid record 13
    Reader r(file);
    std::vector<UdpDatagram> v;
    UdpDatagram d;
    while (r.next(d)) v.push_back(d);
    ASSERT_EQ(v.size(), 12u);
    for (std::size_t i = 0; i < v.size(); ++i) {
        EXPECT_EQ(v[i].payload, pattern(1206, static_cast<unsigned>(i)));
        EXPECT_EQ(v[i].time_ns, static_cast<std::int64_t>(i) * 1000);
    }
    EXPECT_EQ(r.count(FrameStatus::Truncated), 1u);
    EXPECT_FALSE(r.error().empty());
}

TEST(PcapWriter, throws_io_error_naming_an_uncreatable_file) {
    const std::string path = "/nonexistent-dir/x.pcap";
    try {
        Writer w(path);
        FAIL() << "no exception";
    } catch (const mirage::IoError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

}  // namespace
