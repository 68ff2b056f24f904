// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/sensor_faults.hpp"

#include <algorithm>

#include "mirage/core/rng.hpp"

namespace mirage::control {
namespace {

// Streams of the counter-based generator (distinct from the renderer's, docs/control.md §5).
constexpr std::uint32_t kDropStream = 0xD0000000u;
constexpr std::uint32_t kNoiseStream = 0xE0000000u;

}  // namespace

void FaultCell::store(const FaultSettings& f) {
    const auto clamp = [](unsigned v, unsigned hi) { return std::uint64_t{std::min(v, hi)}; };
    const std::uint64_t w = clamp(f.drop_rate, 10000) | clamp(f.drop_burst, 1000) << 14 |
                            std::uint64_t{static_cast<std::uint16_t>(f.range_bias_mm)} << 24 |
                            clamp(f.range_noise_mm, 10000) << 40 |
                            std::uint64_t{f.freeze_nav} << 54 | std::uint64_t{f.stale_nav} << 55 |
                            std::uint64_t{f.stop} << 56;
    word_.store(w, std::memory_order_relaxed);
}

FaultSettings FaultCell::load() const {
    const std::uint64_t w = word_.load(std::memory_order_relaxed);
    FaultSettings f;
    f.drop_rate = static_cast<std::uint16_t>(w & 0x3FFF);
    f.drop_burst = static_cast<std::uint16_t>(w >> 14 & 0x3FF);
    f.range_bias_mm = static_cast<std::int16_t>(static_cast<std::uint16_t>(w >> 24));
    f.range_noise_mm = static_cast<std::uint16_t>(w >> 40 & 0x3FFF);
    f.freeze_nav = w >> 54 & 1;
    f.stale_nav = w >> 55 & 1;
    f.stop = w >> 56 & 1;
    return f;
}

bool PacketDropper::drop(const FaultSettings& f) {
    const std::uint64_t k = packet_++;
    if (burst_left_ == 0 && f.drop_rate > 0) {
        core::PulseRng rng(seed_, k, kDropStream + sensor_);
        if (rng.uniform() * 10000.0 < f.drop_rate)
            burst_left_ = std::max<std::uint16_t>(f.drop_burst, 1);
    }
    if (burst_left_ == 0) return false;
    --burst_left_;
    ++dropped_;
    return true;
}

void FaultPacketizer::add(std::span<const core::PointRecord> points) {
    const FaultSettings f = cell_.load();
    if (f.stale_nav) {
        if (!stale_) stale_periods_.fetch_add(1, std::memory_order_relaxed);
        stale_ = true;
        stale_points_.fetch_add(points.size(), std::memory_order_relaxed);
        return;
    }
    stale_ = false;
    points_.fetch_add(points.size(), std::memory_order_relaxed);
    if (f.range_bias_mm == 0 && f.range_noise_mm == 0) {
        inner_.add(points);
        return;
    }
    buf_.assign(points.begin(), points.end());
    for (auto& p : buf_) {
        double r = p.range_m + 1e-3 * f.range_bias_mm;
        if (f.range_noise_mm > 0) {
            core::PulseRng rng(seed_, p.pulse, kNoiseStream + sensor_ * 16u + p.return_number);
            r += 1e-3 * f.range_noise_mm * rng.normal();
        }
        p.range_m = static_cast<float>(std::max(r, 0.0));
    }
    inner_.add(buf_);
}

}  // namespace mirage::control
