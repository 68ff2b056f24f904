// SPDX-License-Identifier: Apache-2.0
// A sensor clock on the host's clock follows its steps (docs/time.md §1): the packet output polls
// the follower, the encoder adds the step to the next packets' timestamps, the capture to its
// record times, so a timestamp stays one packet's span before its record throughout; the
// schedule (the packets' sensor-clock send times) runs on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mirage/hostclock/clock_step.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/sensor_clock.hpp"

namespace mirage {
namespace {

TEST(PacketOutputClockStep, CaptureAndTimestampsFollowAStep) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("mirage_clock_step_" + std::to_string(::getpid()) + ".pcap");
    std::atomic<std::int64_t> host{5'000'000'000};  // the host's GPS time − monotonic
    hostclock::ClockStepFollower follow([&host] { return host.load(); }, {100'000, 0});
    output::PacketOutputOptions po;
    po.realtime = false;  // as fast as possible: the step comes from the fake source
    po.status_line = false;
    po.pcap_path = path.string();
    po.clock_follower = &follow;
    const auto& md = velodyne::descriptor(velodyne::Model::Vlp16);
    velodyne::PacketizerOptions vo;
    vo.start = core::parse_time("2024-01-01T00:10:00Z");
    vo.position_packets = false;
    vo.clock_step = &follow.step();
    std::optional<output::PacketOutput> out;
    std::uint64_t packets = 0;
    constexpr std::int64_t kStep = -3'000'000'000;  // the host clock stepped back 3 s
    velodyne::Packetizer pk(md, vo, [&](const wire::PacketView& p) {
        (*out)(p);
        if (++packets == 300) host += kStep;
    });
    out.emplace(po);
    pk.advance_to(600 * pk.pulses_per_packet());
    out->finish();

    const auto d = pcap::read_udp(path.string());
    std::filesystem::remove(path);
    ASSERT_EQ(d.size(), 600u);
    EXPECT_EQ(follow.steps(), 1u);
    int before = 0, after = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        const core::GpsTime sched = pk.packet_send_time(i);
        const std::int64_t record_shift =
            d[i].time_ns - core::unix_ns_from_gps(sched);  // 0, then the step
        ASSERT_TRUE(record_shift == 0 || record_shift == kStep) << i;
        (record_shift == 0 ? before : after)++;
        velodyne::DecodedPacket dp;
        ASSERT_EQ(velodyne::decode_data(d[i].payload, &md, dp), velodyne::DecodeStatus::Ok);
        const std::int64_t stamp_lead_us =
            std::int64_t{velodyne::micros_past_hour(sched + core::Nanos(record_shift))} -
            std::int64_t{dp.timestamp_us};
        EXPECT_GT(stamp_lead_us, 1000) << i;  // one packet's span, step or not
        EXPECT_LT(stamp_lead_us, 1400) << i;
    }
    // The host steps after the 300th packet's output; the 301st packet's output reads it, and
    // the encoder adds it from the 302nd on.
    EXPECT_EQ(before, 301);
    EXPECT_EQ(after, 299);
}

}  // namespace
}  // namespace mirage
