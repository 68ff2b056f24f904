// SPDX-License-Identifier: Apache-2.0
// Deterministic synthetic points shared by the LAS tests.
#pragma once
#include <cstdint>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "mirage/core/point.hpp"

namespace mirage::test {

// GPS instant in 2024 (≈ 1.39e9 s after the GPS epoch) plus k · 1.234567 ms.
inline core::GpsTime test_time(std::uint64_t k) {
    return core::GpsTime(
        core::Nanos(1'388'000'000'123'456'789LL + static_cast<std::int64_t>(k) * 1'234'567LL));
}

// Adjusted standard GPS time computed here from the integer nanoseconds (test oracle).
inline double expected_adjusted_gps(core::GpsTime t) {
    const std::int64_t ns = t.time_since_epoch().count() - 1'000'000'000LL * 1'000'000'000LL;
    return static_cast<double>(ns / 1'000'000'000LL) +
           static_cast<double>(ns % 1'000'000'000LL) * 1e-9;
}

// Points with every field varied; local coordinates within ±half_extent_m.
inline std::vector<core::PointRecord> make_points(std::size_t n, std::uint32_t seed,
                                                  int max_returns = 5, int max_class = 31,
                                                  double half_extent_m = 500.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-half_extent_m, half_extent_m);
    std::uniform_real_distribution<double> height(-20.0, 80.0);
    std::uniform_int_distribution<int> u16(0, 65535);
    std::uniform_int_distribution<int> nret(1, max_returns);
    std::uniform_int_distribution<int> cls(0, max_class);
    std::uniform_real_distribution<float> angle(-89.0f, 89.0f);
    std::vector<core::PointRecord> pts(n);
    for (std::size_t k = 0; k < n; ++k) {
        core::PointRecord& p = pts[k];
        p.x = pos(rng);
        p.y = pos(rng);
        p.z = height(rng);
        p.t = test_time(k);
        p.pulse = k;
        p.range_m = static_cast<float>(10.0 + static_cast<double>(k % 100));
        p.scan_angle_deg = angle(rng);
        p.azimuth_deg = static_cast<float>((k * 7) % 360);
        p.intensity = static_cast<std::uint16_t>(u16(rng));
        p.channel = static_cast<std::uint16_t>(k % 16);
        p.point_source_id = static_cast<std::uint16_t>(u16(rng));
        p.red = static_cast<std::uint16_t>(u16(rng));
        p.green = static_cast<std::uint16_t>(u16(rng));
        p.blue = static_cast<std::uint16_t>(u16(rng));
        p.number_of_returns = static_cast<std::uint8_t>(nret(rng));
        p.return_number = static_cast<std::uint8_t>(
            std::uniform_int_distribution<int>(1, p.number_of_returns)(rng));
        p.classification = static_cast<std::uint8_t>(cls(rng));
        p.scan_direction = static_cast<std::uint8_t>(k % 2);
        p.edge_of_flight_line = static_cast<std::uint8_t>(k % 7 == 0);
    }
    return pts;
}

inline std::vector<std::uint8_t> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
}

}  // namespace mirage::test
