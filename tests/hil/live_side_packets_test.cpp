// SPDX-License-Identifier: Apache-2.0
// `mirage live` with Velodyne position packets on: each leaves at its own time, not after the
// window of pulses that follows it has been rendered (docs/live-navigation.md §1). Measured on
// loopback with kernel receive timestamps: a packet's delay is its arrival − its sensor time
// (send time for data packets, the position packet's own time), and the position packets' median
// delay must match the data packets'. Emitted with the next data packet instead, they arrive a
// uniform 0–1.3 ms later (median ≈ 0.65 ms).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <vector>

#include "cli_run.hpp"
#include "live_yard.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// Arrival (CLOCK_REALTIME ns) − sensor time (µs past the hour, unwrapped near `ref_us`), in µs.
double delay_us(std::int64_t arrival_ns, std::int64_t t_us, std::int64_t ref_us) {
    constexpr std::int64_t kHourUs = 3'600'000'000;
    if (t_us - ref_us < -kHourUs / 2) t_us += kHourUs;
    if (t_us - ref_us > kHourUs / 2) t_us -= kHourUs;
    return double(arrival_ns / 1000 - t_us);
}

TEST(LiveSidePackets, position_packets_leave_at_their_own_time) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    Collector data, position;
    const auto r = run_mirage(
        "live --scene " + scene + " --nav sbg-can:memory:side --fake-ins " + traj +
        " --sensor vlp16 --sub-rays 1 --no-noise --duration 3 --no-status --first-nav-timeout 15"
        " --max-extrapolation-ms 150 --to 127.0.0.1 --data-port " +
        std::to_string(data.port()) + " --position-port " + std::to_string(position.port()));
    data.stop();
    position.stop();
    ASSERT_EQ(r.exit_code, 0) << r.output;

    // A data packet's timestamp is its first firing; it is sent at its last.
    const velodyne::ModelDescriptor& md = velodyne::descriptor(velodyne::Model::Vlp16);
    const velodyne::Packetizer pk(md, velodyne::PacketizerOptions{}, {});
    const std::int64_t span_us = (pk.packet_send_time(0) - pk.sequence_time(0)).count() / 1000;

    std::vector<double> data_delay, position_delay;
    std::int64_t ref_us = -1;
    velodyne::DecodedPacket dp;
    for (std::size_t i = 0; i < data.packets().size(); ++i) {
        const auto& bytes = data.packets()[i];
        const std::int64_t arrival = data.kernel_times()[i];
        if (arrival == 0 || bytes.size() != velodyne::kDataPacketSize ||
            velodyne::decode_data(bytes, nullptr, dp) != velodyne::DecodeStatus::Ok)
            continue;
        if (ref_us < 0) ref_us = dp.timestamp_us;
        data_delay.push_back(delay_us(arrival, dp.timestamp_us + span_us, ref_us));
    }
    velodyne::DecodedPosition pos;
    for (std::size_t i = 0; i < position.packets().size(); ++i) {
        ASSERT_EQ(velodyne::decode_position(position.packets()[i], pos),
                  velodyne::PositionStatus::Ok);
        const std::int64_t arrival = position.kernel_times()[i];
        if (arrival != 0 && ref_us >= 0)
            position_delay.push_back(delay_us(arrival, pos.timestamp_us, ref_us));
    }
    // 3 s of VLP-16: 754 data packets/s, a position packet every 18.6 ms (~161).
    ASSERT_GT(data_delay.size(), 2100u) << r.output;
    ASSERT_GT(position_delay.size(), 140u) << r.output;
    const double d_data = median(data_delay), d_pos = median(position_delay);
    std::printf(
        "median arrival - sensor time: position packets %+.0f µs from the data packets' "
        "(%zu position, %zu data packets)\n",
        d_pos - d_data, position_delay.size(), data_delay.size());
    EXPECT_LT(d_pos - d_data, 250.0);
    EXPECT_GT(d_pos - d_data, -250.0);
}

}  // namespace
}  // namespace mirage::test
