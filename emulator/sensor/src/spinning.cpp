// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/spinning.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "mirage/core/error.hpp"
#include "scan_math.hpp"

namespace mirage::sensor {

SpinningPattern::SpinningPattern(SpinningConfig config) : config_(std::move(config)) {
    const auto fail = [](const std::string& what) {
        throw ConfigError("sensor: spinning: " + what);
    };
    if (config_.lasers.empty()) fail("no lasers");
    if (config_.lasers.size() > 65535) fail("more than 65535 lasers");
    if (!(config_.sequence_period_ns >= 1.0) || !std::isfinite(config_.sequence_period_ns))
        fail("sequence period must be at least 1 ns");
    if (!(config_.rotation_hz > 0) || !std::isfinite(config_.rotation_hz))
        fail("rotation rate must be positive");
    double first = config_.lasers.front().firing_offset_ns;
    for (const auto& l : config_.lasers) first = std::min(first, l.firing_offset_ns);
    // Rounded offsets stay below the shortest rounded period, so t_ns never decreases.
    const double last_allowed = std::floor(config_.sequence_period_ns) - 1.0;
    for (std::size_t i = 0; i < config_.lasers.size(); ++i) {
        auto& l = config_.lasers[i];
        if (!std::isfinite(l.firing_offset_ns) || l.firing_offset_ns < 0 ||
            std::round(l.firing_offset_ns) > last_allowed)
            fail("laser " + std::to_string(i) + ": firing offset outside [0, sequence period)");
        if (!(std::abs(l.elevation_deg) <= 90.0))
            fail("laser " + std::to_string(i) + ": elevation outside [−90°, 90°]");
        if (!std::isfinite(l.azimuth_offset_deg))
            fail("laser " + std::to_string(i) + ": azimuth offset is not a number");
        l.firing_offset_ns -= first;  // pulse 0 fires at t = 0
    }

    // Azimuth per ns as 360/rev_ns keeps Ouster steps (360/W) exact in binary.
    const double rev_ns = 1e9 / config_.rotation_hz;
    step_deg_ = 360.0 * config_.sequence_period_ns / rev_ns;

    std::vector<std::size_t> order(config_.lasers.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return config_.lasers[a].firing_offset_ns < config_.lasers[b].firing_offset_ns;
    });
    slots_.reserve(order.size());
    for (std::size_t l : order) {
        const LaserSpec& s = config_.lasers[l];
        const double el = s.elevation_deg * std::numbers::pi / 180.0;
        Slot slot{static_cast<std::uint16_t>(l),
                  std::llround(s.firing_offset_ns),
                  360.0 * s.firing_offset_ns / rev_ns + s.azimuth_offset_deg,
                  std::cos(el),
                  std::sin(el),
                  static_cast<float>(s.elevation_deg)};
        slot.base_wrapped_deg = detail::wrap_deg(slot.azimuth_base_deg);
        const double b = slot.base_wrapped_deg * std::numbers::pi / 180.0;
        slot.ecos_base = slot.cos_el * std::cos(b);
        slot.esin_base = slot.cos_el * std::sin(b);
        slots_.push_back(slot);
    }
}

double SpinningPattern::pulse_rate_hz() const {
    return static_cast<double>(slots_.size()) * 1e9 / config_.sequence_period_ns;
}

std::int64_t SpinningPattern::time_ns(std::uint64_t k) const {
    const std::uint64_t lasers = slots_.size();
    const double s = static_cast<double>(k / lasers);
    return std::llround(s * config_.sequence_period_ns) + slots_[k % lasers].offset_ns;
}

std::uint64_t SpinningPattern::pulse_count(core::Nanos duration) const {
    const double sequences = static_cast<double>(duration.count()) / config_.sequence_period_ns;
    const std::uint64_t hi =
        (static_cast<std::uint64_t>(std::max(0.0, sequences)) + 2) * slots_.size();
    return detail::count_before(duration.count(), hi,
                                [this](std::uint64_t k) { return time_ns(k); });
}

void SpinningPattern::pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const {
    const std::uint64_t lasers = slots_.size();
    std::uint64_t seq = first / lasers;
    std::size_t si = static_cast<std::size_t>(first % lasers);
    // Rotor state of the current sequence: one sincos per sequence instead of one per pulse.
    std::int64_t t_seq = 0;
    double rotor_deg = 0, cr = 1, sr = 0;
    auto start_sequence = [&] {
        const double s = static_cast<double>(seq);
        t_seq = std::llround(s * config_.sequence_period_ns);
        rotor_deg = detail::wrap_deg(s * step_deg_);
        const double a = rotor_deg * std::numbers::pi / 180.0;
        cr = std::cos(a);
        sr = std::sin(a);
    };
    start_sequence();
    for (std::size_t i = 0; i < n; ++i) {
        const Slot& slot = slots_[si];
        PulseSpec& p = out[i];
        p.t_ns = t_seq + slot.offset_ns;
        double az = rotor_deg + slot.base_wrapped_deg;
        if (az >= 360.0) az -= 360.0;
        // cos(r + b), sin(r + b) by angle addition, already scaled by cos(elevation).
        const double x = cr * slot.ecos_base - sr * slot.esin_base;
        const double y = sr * slot.ecos_base + cr * slot.esin_base;
        p.dir = Eigen::Vector3f(static_cast<float>(x), static_cast<float>(-y),
                                static_cast<float>(slot.sin_el));
        p.channel = slot.channel;
        p.scan_angle_deg = slot.elevation_deg;
        p.azimuth_deg = static_cast<float>(az);
        if (p.azimuth_deg >= 360.0f) p.azimuth_deg = 0.0f;  // float rounding of 359.99999…
        p.scan_direction = 0;
        p.edge_of_flight_line = 0;
        if (++si == lasers) {
            si = 0;
            ++seq;
            if (i + 1 < n) start_sequence();
        }
    }
}

}  // namespace mirage::sensor
