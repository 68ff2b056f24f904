// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test helpers: random samples and a collecting decoder.
#include <numbers>
#include <random>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/ncom/decoder.hpp"
#include "mirage/ncom/encoder.hpp"

namespace mirage::ncom::test {

inline nav::NavSample random_sample(std::mt19937_64& rng, std::int64_t t_ns) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double pi = std::numbers::pi;
    nav::NavSample s;
    s.source = nav::Protocol::Ncom;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude | nav::NavSample::kAcceleration |
               nav::NavSample::kAngularRate;
    s.t = core::GpsTime(core::Nanos(t_ns));
    s.lat_deg = 89.9 * u(rng);
    s.lon_deg = 179.9 * u(rng);
    s.height_m = 2000.0 + 1000.0 * u(rng);
    s.velocity_ned_mps = {60 * u(rng), 60 * u(rng), 5 * u(rng)};
    s.heading_rad = pi * (1.0 + 0.9999 * u(rng));
    s.pitch_rad = 0.49 * pi * u(rng);
    s.roll_rad = 0.99 * pi * u(rng);
    s.accel_frd_mps2 = {20 * u(rng), 20 * u(rng), -9.81 + 20 * u(rng)};
    s.rate_frd_radps = {2 * u(rng), 2 * u(rng), 2 * u(rng)};
    s.satellites = static_cast<std::uint8_t>(rng() % 30);
    const nav::FixQuality qs[] = {nav::FixQuality::Autonomous, nav::FixQuality::Differential,
                                  nav::FixQuality::RtkFloat, nav::FixQuality::RtkFixed,
                                  nav::FixQuality::DeadReckoning};
    s.quality = qs[rng() % 5];
    return s;
}

struct Collect {
    NcomDecoder dec;
    std::vector<nav::NavSample> out;
    nav::SampleFn fn() {
        return [this](const nav::NavSample& s) { out.push_back(s); };
    }
    void feed(std::span<const std::uint8_t> b) { dec.feed(b, fn()); }
    void datagram(std::span<const std::uint8_t> b) { dec.feed_datagram(b, fn()); }
};

// A 10 ms stream starting at t0 (ns), from random samples.
inline std::vector<std::array<std::uint8_t, kPacketSize>> make_packets(int n, std::uint64_t seed,
                                                                       std::int64_t t0_ns,
                                                                       EncoderOptions opt = {}) {
    std::mt19937_64 rng(seed);
    NcomEncoder enc(opt);
    std::vector<std::array<std::uint8_t, kPacketSize>> out;
    for (int i = 0; i < n; ++i)
        out.push_back(enc.encode(random_sample(rng, t0_ns + i * 10'000'000LL)));
    return out;
}

inline std::vector<std::uint8_t> concat(
    const std::vector<std::array<std::uint8_t, kPacketSize>>& pkts) {
    std::vector<std::uint8_t> all;
    for (const auto& p : pkts) all.insert(all.end(), p.begin(), p.end());
    return all;
}

inline constexpr std::int64_t kT0 = 1'400'000'000LL * 1'000'000'000LL;  // a minute boundary

}  // namespace mirage::ncom::test
