// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "raw_pcap.hpp"
#include "mirage/core/error.hpp"
#include "mirage/replay/impairer.hpp"
#include "mirage/replay/options.hpp"
#include "mirage/replay/replayer.hpp"
#include "test_paths.hpp"

namespace {

using namespace mirage::replay;
using mirage::test::Bytes;
using mirage::test::TempDir;

std::vector<Packet> numbered(std::size_t n) {
    std::vector<Packet> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        v[i].time_ns = static_cast<std::int64_t>(i) * 1000;
        v[i].payload = {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8),
                        static_cast<std::uint8_t>(i >> 16)};
    }
    return v;
}
std::size_t id(const Packet& p) {
    return std::size_t{p.payload[0]} | (std::size_t{p.payload[1]} << 8) |
           (std::size_t{p.payload[2]} << 16);
}
std::vector<Packet> run(const ImpairmentConfig& c, std::size_t n, ImpairmentCounters* k = nullptr) {
    Impairer imp(c);
    std::vector<Packet> out;
    for (auto& p : numbered(n)) imp.push(std::move(p), out);
    imp.finish(out);
    if (k) *k = imp.counters();
    return out;
}

TEST(ReplayOptions, parses_port_maps_and_decimal_seconds_exactly) {
    const auto m = parse_port_map({"2368=12368", "8308=18308"});
    EXPECT_EQ(m.at(2368), 12368);
    EXPECT_EQ(m.at(8308), 18308);
    EXPECT_THROW(parse_port_map({"2368:1"}), mirage::ConfigError);
    EXPECT_THROW(parse_port_map({"2368=70000"}), mirage::ConfigError);
    EXPECT_EQ(parse_seconds_ns("1.5", "t"), 1'500'000'000);
    EXPECT_EQ(parse_seconds_ns("0.000000001", "t"), 1);
    EXPECT_EQ(parse_seconds_ns("3", "t"), 3'000'000'000);
    EXPECT_EQ(parse_seconds_ns(".25", "t"), 250'000'000);
    EXPECT_THROW(parse_seconds_ns("-1", "t"), mirage::ConfigError);
    EXPECT_THROW(parse_seconds_ns("1e3", "t"), mirage::ConfigError);
    EXPECT_EQ(parse_listen_ports(":2368,:8308"), (std::vector<std::uint16_t>{2368, 8308}));
    EXPECT_EQ(parse_listen_ports("0.0.0.0:0"), (std::vector<std::uint16_t>{0}));
}

TEST(Impairer, no_impairment_passes_every_packet_unchanged) {
    ImpairmentCounters k;
    const auto out = run({}, 1000, &k);
    ASSERT_EQ(out.size(), 1000u);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(id(out[i]), i);
        EXPECT_EQ(out[i].time_ns, static_cast<std::int64_t>(i) * 1000);
    }
    EXPECT_EQ(k.dropped + k.duplicated + k.reordered, 0u);
}

TEST(Impairer, drop_rate_and_bursts_follow_the_configuration) {
    const std::size_t n = 100'000;
    ImpairmentConfig c;
    c.drop = 0.02;
    c.drop_burst = 5;
    c.seed = 42;
    ImpairmentCounters k;
    const auto out = run(c, n, &k);
    EXPECT_EQ(out.size() + k.dropped, n);
    // Events start only at non-dropped packets: expected events = n p / (1 + p (N − 1)).
    const double expect = n * 0.02 / (1 + 0.02 * 4);
    const double sigma = std::sqrt(expect);
    EXPECT_NEAR(static_cast<double>(k.drop_events), expect, 5 * sigma);
    // Every gap in the surviving sequence is a whole number of bursts of 5.
    std::size_t prev = 0;
    bool first = true;
    for (const auto& p : out) {
        const std::size_t gap = first ? id(p) : id(p) - prev - 1;
        EXPECT_EQ(gap % 5, 0u) << "at " << id(p);
        prev = id(p);
        first = false;
    }
    EXPECT_LE(5 * k.drop_events - k.dropped, 4u);  // only a burst at the very end is cut short
}

TEST(Impairer, same_seed_same_output_different_seed_different_output) {
    ImpairmentConfig c;
    c.drop = 0.05;
    c.duplicate = 0.05;
    c.reorder = 0.05;
    c.jitter_ns = 10'000;
    c.seed = 7;
    const auto a = run(c, 5000), b = run(c, 5000);
    c.seed = 8;
    const auto d = run(c, 5000);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].payload, b[i].payload);
        EXPECT_EQ(a[i].time_ns, b[i].time_ns);
    }
    bool differ = a.size() != d.size();
    for (std::size_t i = 0; !differ && i < a.size(); ++i) differ = a[i].payload != d[i].payload;
    EXPECT_TRUE(differ);
}

TEST(Impairer, duplicates_follow_their_original_and_reorders_swap_neighbours) {
    ImpairmentConfig c;
    c.duplicate = 0.1;
    c.seed = 3;
    ImpairmentCounters k;
    auto out = run(c, 20'000, &k);
    EXPECT_EQ(out.size(), 20'000 + k.duplicated);
    EXPECT_NEAR(static_cast<double>(k.duplicated), 2000.0, 5 * std::sqrt(1800.0));
    std::size_t dups = 0;
    for (std::size_t i = 1; i < out.size(); ++i)
        if (id(out[i]) == id(out[i - 1])) {
            ++dups;
            EXPECT_EQ(out[i].time_ns, out[i - 1].time_ns);
        }
    EXPECT_EQ(dups, k.duplicated);

    c = {};
    c.reorder = 0.1;
    c.seed = 4;
    out = run(c, 20'000, &k);
    ASSERT_EQ(out.size(), 20'000u);
    std::size_t swaps = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        // Times stay on the schedule; payloads move by at most one place.
        EXPECT_EQ(out[i].time_ns, static_cast<std::int64_t>(i) * 1000);
        const auto d = static_cast<long>(id(out[i])) - static_cast<long>(i);
        EXPECT_LE(std::abs(d), 1);
        if (d == 1) ++swaps;
    }
    EXPECT_EQ(swaps, k.reordered);
    EXPECT_NEAR(static_cast<double>(k.reordered), 20'000 * 0.1 / 1.1, 5 * std::sqrt(1800.0));
}

TEST(Impairer, jitter_delays_each_packet_by_zero_to_s) {
    ImpairmentConfig c;
    c.jitter_ns = 50'000;
    const auto out = run(c, 10'000);
    std::int64_t lo = INT64_MAX, hi = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const auto extra = out[i].time_ns - static_cast<std::int64_t>(id(out[i])) * 1000;
        lo = std::min(lo, extra);
        hi = std::max(hi, extra);
    }
    EXPECT_GE(lo, 0);
    EXPECT_LE(hi, 50'000);
    EXPECT_GT(hi, 45'000);  // the range is used
    EXPECT_LT(lo, 5'000);
    ImpairmentConfig bad;
    bad.drop = 1.5;
    EXPECT_THROW(Impairer{bad}, mirage::ConfigError);
    bad.drop = 0;
    bad.drop_burst = 0;
    EXPECT_THROW(Impairer{bad}, mirage::ConfigError);
}

// Bad input: everything before a damaged record is sent, and the error names its byte offset;
// non-UDP frames and frames cut by the snap length are skipped and counted.
TEST(ReplayBadInput, truncated_file_replays_what_came_before_and_names_the_offset) {
    using namespace mirage::test;
    TempDir dir;
    const auto file = dir.file("bad.pcap");
    const auto frame = ethernet(0x0800, ipv4(17, udp(2368, 2368, pattern(300))));
    Bytes cut = frame;
    cut.resize(40);
    std::vector<RawRecord> recs = {{1000, frame},
                                   {2000, ethernet(0x0806, Bytes(28, 0))},        // ARP
                                   {3000, ethernet(0x0800, ipv4(6, Bytes(20, 0)))},  // TCP
                                   {4000, cut, static_cast<std::uint32_t>(frame.size())},
                                   {5000, frame},
                                   {6000, frame}};
    write_raw_pcap(file, 1, recs);
    std::size_t good = 24;
    for (std::size_t i = 0; i < 5; ++i) good += 16 + recs[i].frame.size();
    std::filesystem::resize_file(file, good + 30);  // the last record is cut mid-way
    ReplayConfig c;
    c.path = file;
    c.port_map = {{2368, 9}};  // discard port; nothing needs to listen for a send to succeed
    c.speed = 0;
    const auto s = replay(c);
    EXPECT_EQ(s.packets, 2u);
    EXPECT_EQ(s.bytes, 600u);
    EXPECT_EQ(s.error_offset, static_cast<std::int64_t>(good));
    EXPECT_NE(s.error.find("byte " + std::to_string(good)), std::string::npos) << s.error;
    using mirage::pcap::FrameStatus;
    EXPECT_EQ(s.frames[static_cast<std::size_t>(FrameStatus::NotIpv4)], 1u);
    EXPECT_EQ(s.frames[static_cast<std::size_t>(FrameStatus::NotUdp)], 1u);
    EXPECT_EQ(s.frames[static_cast<std::size_t>(FrameStatus::Truncated)], 2u);  // snap + cut
    const auto text = format_summary(s);
    EXPECT_NE(text.find("ERROR"), std::string::npos) << text;
    std::cout << text;
}

TEST(ReplayBadInput, corrupt_header_and_unknown_link_type_give_clear_results) {
    using namespace mirage::test;
    TempDir dir;
    {
        std::ofstream(dir.file("junk.pcap")) << "this is not a capture file at all";
    }
    ReplayConfig c;
    c.path = dir.file("junk.pcap");
    c.speed = 0;
    try {
        replay(c);
        FAIL() << "no exception";
    } catch (const mirage::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("junk.pcap"), std::string::npos) << e.what();
    }
    // A record header claiming 1 GiB: libpcap refuses it; the error names where it starts.
    const auto frame = ethernet(0x0800, ipv4(17, udp(2368, 2368, pattern(10))));
    write_raw_pcap(dir.file("huge.pcap"), 1, {{1, frame}, {2, frame}});
    {
        std::fstream f(dir.file("huge.pcap"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(24 + 16 + frame.size() + 8));
        const char big[4] = {0, 0, 0, 0x40};
        f.write(big, 4);
    }
    c.path = dir.file("huge.pcap");
    c.port_map = {{2368, 9}};
    auto s = replay(c);
    EXPECT_EQ(s.packets, 1u);
    EXPECT_EQ(s.error_offset, static_cast<std::int64_t>(24 + 16 + frame.size()));
    std::cout << s.error << "\n";

    write_raw_pcap(dir.file("wifi.pcap"), 105, {{1, Bytes(40, 1)}, {2, Bytes(40, 1)}});
    c.path = dir.file("wifi.pcap");
    s = replay(c);
    EXPECT_EQ(s.packets, 0u);
    EXPECT_FALSE(s.link_supported);
    EXPECT_EQ(s.frames[static_cast<std::size_t>(mirage::pcap::FrameStatus::NotIpv4)], 2u);
    EXPECT_NE(format_summary(s).find("link type 105"), std::string::npos) << format_summary(s);
}

TEST(ReplaySchedule, from_until_and_loops_select_and_repeat_the_datagrams) {
    using namespace mirage::test;
    TempDir dir;
    std::vector<RawRecord> recs;
    for (int i = 0; i < 10; ++i)
        recs.push_back({1'000'000'000 + i * 1'000'000,
                        ethernet(0x0800, ipv4(17, udp(1, 2368, {static_cast<std::uint8_t>(i)})))});
    write_raw_pcap(dir.file("ten.pcap"), 1, recs);
    ReplayConfig c;
    c.path = dir.file("ten.pcap");
    c.port_map = {{2368, 9}};
    c.speed = 0;
    c.from_ns = 2'000'000;
    c.until_ns = 7'000'000;  // datagrams 2..6
    c.loops = 3;
    const auto s = replay(c);
    EXPECT_EQ(s.packets, 15u);
    EXPECT_EQ(s.passes, 3u);
    EXPECT_EQ(s.out_of_range, 9u);  // 2 before + the first past --until, each pass
    c.speed = -1;
    EXPECT_THROW(replay(c), mirage::ConfigError);
}

}  // namespace
