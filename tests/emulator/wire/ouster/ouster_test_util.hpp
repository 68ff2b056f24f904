// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "mirage/core/point.hpp"
#include "mirage/ouster/packetizer.hpp"

namespace mirage::ouster::test {

struct Captured {
    wire::Stream stream;
    core::GpsTime time;
    std::vector<std::uint8_t> bytes;
};

// Random single returns for pulses [0, n): ~20 % misses, ranges within `max_range_m`.
inline std::vector<core::PointRecord> random_returns(const Descriptor& d, std::uint64_t n,
                                                     double max_range_m, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<core::PointRecord> pts;
    for (std::uint64_t k = 0; k < n; ++k) {
        if (u(rng) < 0.2) continue;
        core::PointRecord p;
        p.pulse = k;
        p.channel = static_cast<std::uint16_t>(k % d.beams);
        p.range_m = static_cast<float>(0.5 + u(rng) * (max_range_m - 0.5));
        p.intensity = static_cast<std::uint16_t>(u(rng) * 65535.0);
        p.n_laser = std::floor(u(rng) * 60000.0);
        pts.push_back(p);
    }
    return pts;
}

// Runs a packetizer over `points` (delivered in chunks, as the pipeline does) up to `pulses`.
inline void packetize(OusterPacketizer& pk, const std::vector<core::PointRecord>& points,
                      std::uint64_t pulses, std::uint64_t chunk = 4096) {
    std::size_t i = 0;
    for (std::uint64_t next = 0; next < pulses;) {
        next = std::min(pulses, next + chunk);
        std::size_t j = i;
        while (j < points.size() && points[j].pulse < next) ++j;
        pk.add(std::span(points).subspan(i, j - i));
        pk.advance_to(next);
        i = j;
    }
    pk.finish();
}

inline wire::PacketFn collect(std::vector<Captured>& out) {
    return [&out](const wire::PacketView& v) {
        out.push_back(
            {v.stream, v.time, std::vector<std::uint8_t>(v.bytes.begin(), v.bytes.end())});
    };
}

}  // namespace mirage::ouster::test
