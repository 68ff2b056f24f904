// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random NavSamples for round trips (fixed seeds: deterministic).
#include <numbers>
#include <random>

#include "mirage/core/time.hpp"
#include "mirage/nav/nav_sample.hpp"

namespace mirage::novatel::test {

// Time on a whole ms (the long header carries ms); full INS fields.
inline nav::NavSample random_sample(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double pi = std::numbers::pi;
    nav::NavSample s;
    s.source = nav::Protocol::Novatel;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude;
    const auto week = static_cast<std::int32_t>(1000 + rng() % 2000);
    const auto ms = static_cast<std::int64_t>(rng() % 604'800'000ULL);
    s.t = core::from_week_time(week, ms * 1'000'000);
    s.lat_deg = -89.9 + 179.8 * u(rng);
    s.lon_deg = -179.9 + 359.8 * u(rng);
    s.height_m = -100.0 + 5000.0 * u(rng);
    s.velocity_ned_mps = {-50 + 100 * u(rng), -50 + 100 * u(rng), -5 + 10 * u(rng)};
    s.roll_rad = (-1.0 + 2.0 * u(rng)) * pi * 0.99;
    s.pitch_rad = (-1.0 + 2.0 * u(rng)) * pi * 0.49;
    s.heading_rad = 2 * pi * u(rng) * 0.9999;
    const nav::FixQuality qs[] = {nav::FixQuality::Autonomous, nav::FixQuality::Differential,
                                  nav::FixQuality::RtkFloat, nav::FixQuality::RtkFixed};
    s.quality = qs[rng() % 4];
    return s;
}

}  // namespace mirage::novatel::test
