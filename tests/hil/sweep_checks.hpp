// SPDX-License-Identifier: Apache-2.0
// The assertions shared by the pcap and live PCL tests: every point on the room's planes, and
// every full revolution holding the model's number of firings.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pcl_harness.hpp"
#include "room_check.hpp"

namespace mirage::test {

// `mirage emulate` arguments common to both paths.
inline std::vector<std::string> emulate_args(const SensorSetup& s, const std::string& sensor,
                                             const std::string& scene, bool noise) {
    std::vector<std::string> a = {
        "emulate",    "--sensor", sensor,
        "--scene",    scene,      "--pose",
        s.pose_arg(), "--rpm",    std::to_string(static_cast<int>(s.rpm))};
    if (noise) {
        a.insert(a.end(), {"--seed", "1"});
    } else {
        a.push_back("--no-noise");
    }
    return a;
}

struct SweepSummary {
    std::size_t full = 0;          // sweeps after PCL's first (which starts mid-turn)
    std::size_t exact = 0;         // full sweeps holding the model's number of firings
    std::size_t lost_packets = 0;  // whole packets missing from the other full sweeps
    double mean_points = 0;
    GeometryStats geometry;
};

// Every Velodyne data packet carries 12 blocks of 32 channels, whatever the model.
inline constexpr std::size_t kPointsPerVelodynePacket = 12 * 32;

// A loopback UDP socket drops datagrams when the host stalls the reader long enough to fill its
// receive buffer (seen on a loaded 2-core CI machine: 20 packets in one revolution). A live sweep
// may therefore be short by whole packets (summed over neighbouring sweeps when the lost burst
// held the wrap), and only by whole packets; a pcap sweep may not.
enum class PacketLoss { Forbidden, WholePacketsAllowed };

// PCL emits a sweep when the azimuth wraps; the first one starts wherever the stream did and the
// trailing partial one is never emitted, so revolutions 2..n are full. A full revolution is a
// whole number of firing sequences (PCL splits sweeps between sequences) and holds N = 60 s /
// (rpm · period) of them (VLP-16 at 600 rpm: 1808.45, so 1808 or 1809). Block azimuths are
// rounded to 0.01° on the wire, which can move a wrap by one sequence when the rotor is within
// 0.005° of 360°: hence |count/L − N| < 2 rather than < 1.
inline SweepSummary expect_room_sweeps(const std::vector<SweepCollector::Cloud::ConstPtr>& sweeps,
                                       const SensorSetup& setup, const RoomChecker& checker,
                                       std::size_t min_full, const char* label,
                                       PacketLoss loss = PacketLoss::Forbidden) {
    SweepSummary out;
    const auto lasers =
        static_cast<std::size_t>(setup.descriptor().lasers * setup.points_per_firing);
    const double n_seq = setup.sequences_per_rev();
    const double model_points = n_seq * static_cast<double>(lasers);
    const auto packet = static_cast<double>(kPointsPerVelodynePacket);
    EXPECT_GE(sweeps.size(), min_full + 1) << label;
    std::string counts;
    double missing = 0;   // points the current run of short sweeps lacks
    std::size_t run = 0;  // its sweeps
    // A run of short sweeps ending before sweep `end` must lack k ≥ 1 whole packets, give or
    // take the wrap's two sequences per sweep.
    const auto settle = [&](std::size_t end) {
        if (run == 0) return;
        const double k = std::round(missing / packet);
        const bool whole_packets =
            loss == PacketLoss::WholePacketsAllowed && k >= 1.0 &&
            std::abs(missing - k * packet) < 2.0 * double(run) * static_cast<double>(lasers);
        if (whole_packets) out.lost_packets += static_cast<std::size_t>(k);
        EXPECT_TRUE(whole_packets) << label << " sweeps " << end - run << " to " << end - 1
                                   << " lack " << missing << " points of the model's";
        missing = 0;
        run = 0;
    };
    for (std::size_t i = 0; i < sweeps.size(); ++i) {
        const GeometryStats g = checker.check(*sweeps[i]);
        out.geometry.merge(g);
        counts += (i ? " " : "") + std::to_string(sweeps[i]->size());
        if (i == 0) continue;
        ++out.full;
        const std::size_t n = sweeps[i]->size();
        out.mean_points += static_cast<double>(n);
        EXPECT_EQ(n % lasers, 0u) << label << " sweep " << i;
        const double off = static_cast<double>(n / lasers) - n_seq;
        if (std::abs(off) < 2.0) {
            ++out.exact;
            settle(i);
            continue;
        }
        // Short: a lost burst that held the azimuth's wrap splits between two sweeps, so the
        // shortfall of a run of short sweeps is judged together.
        missing += model_points - static_cast<double>(n);
        ++run;
    }
    settle(sweeps.size());
    EXPECT_GE(out.exact, min_full) << label << ": full revolutions with the model's count";
    if (out.full) out.mean_points /= static_cast<double>(out.full);
    const auto& g = out.geometry;
    EXPECT_GT(g.points, 0u) << label;
    EXPECT_EQ(g.outside_tolerance, 0u)
        << label << ": worst " << g.worst_m << " m, ratio " << g.worst_ratio;
    EXPECT_LT(g.worst_elevation_mismatch_deg, 0.01) << label;
    std::printf(
        "[%s] sweeps %zu (points: %s); full revolutions %zu (%zu exact, %zu packets lost on the "
        "socket), mean %.1f points/rev (model %.1f); points %zu; distance to plane: worst %.4f m "
        "(%.2f of tolerance), rms "
        "%.4f m; raw PCL points (no firing-delay azimuth) worst %.4f m; elevation mismatch "
        "%.5f deg\n",
        label, sweeps.size(), counts.c_str(), out.full, out.exact, out.lost_packets,
        out.mean_points, model_points, g.points, g.worst_m, g.worst_ratio, g.rms_m, g.worst_raw_m,
        g.worst_elevation_mismatch_deg);
    return out;
}

}  // namespace mirage::test
