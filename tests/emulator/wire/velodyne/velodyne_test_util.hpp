// SPDX-License-Identifier: Apache-2.0
#pragma once
// Synthetic returns in pulse order for a Velodyne preset, and a packet collector.
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "mirage/core/point.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/sensor/spinning.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::velodyne::test {

struct CollectedPacket {
    wire::Stream stream;
    core::GpsTime time;
    std::vector<std::uint8_t> bytes;
};

inline wire::PacketFn collect_into(std::vector<CollectedPacket>& out) {
    return [&out](const wire::PacketView& v) {
        out.push_back(
            {v.stream, v.time, std::vector<std::uint8_t>(v.bytes.begin(), v.bytes.end())});
    };
}

// The preset of a model, turning at `rpm`.
inline sensor::SensorModel preset_at(const ModelDescriptor& md, double rpm) {
    sensor::SensorModel m = sensor::preset(std::string(md.name));
    const auto* sp = dynamic_cast<const sensor::SpinningPattern*>(m.scan.get());
    sensor::SpinningConfig cfg = sp->config();
    cfg.rotation_hz = rpm / 60.0;
    m.scan = std::make_shared<sensor::SpinningPattern>(cfg);
    return m;
}

struct SyntheticOptions {
    std::uint64_t seed = 7;
    double miss_probability = 0.15;  // pulses with no return
    int max_returns = 3;             // 1..max_returns returns per hit pulse
    double min_range_m = 0.5, max_range_m = 125.0;
};

// Returns of pulses [0, n) of `pattern` (several per pulse, increasing range = return number).
inline std::vector<core::PointRecord> synthetic_returns(const sensor::ScanPattern& pattern,
                                                        std::uint64_t n, core::GpsTime start,
                                                        const SyntheticOptions& o = {}) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::vector<sensor::PulseSpec> specs(static_cast<std::size_t>(n));
    pattern.pulses(0, specs.size(), specs.data());
    std::vector<core::PointRecord> out;
    for (std::uint64_t k = 0; k < n; ++k) {
        const sensor::PulseSpec& s = specs[static_cast<std::size_t>(k)];
        if (u01(rng) < o.miss_probability) continue;
        const int count = 1 + static_cast<int>(u01(rng) * o.max_returns) % o.max_returns;
        std::vector<double> ranges;
        for (int r = 0; r < count; ++r)
            ranges.push_back(o.min_range_m + u01(rng) * (o.max_range_m - o.min_range_m));
        std::sort(ranges.begin(), ranges.end());
        for (int r = 0; r < count; ++r) {
            core::PointRecord p;
            p.pulse = k;
            p.t = start + core::Nanos(s.t_ns);
            p.channel = s.channel;
            p.azimuth_deg = s.azimuth_deg;
            p.range_m = static_cast<float>(ranges[static_cast<std::size_t>(r)]);
            p.n_laser = 10.0 + 1000.0 * u01(rng);
            p.intensity = static_cast<std::uint16_t>(u01(rng) * 65535.0);
            p.return_number = static_cast<std::uint8_t>(r + 1);
            p.number_of_returns = static_cast<std::uint8_t>(count);
            out.push_back(p);
        }
    }
    return out;
}

inline double angle_diff_deg(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d < -180.0) d += 360.0;
    return d;
}

}  // namespace mirage::velodyne::test
