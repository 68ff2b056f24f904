// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <vector>

#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {

// One laser of a spinning multi-beam sensor (docs/wire-formats.md §1.7 / §2.7).
struct LaserSpec {
    double elevation_deg = 0;
    double azimuth_offset_deg = 0;  // added to the rotor azimuth (clockwise), = −rot_correction
    double firing_offset_ns = 0;    // within a firing sequence, [0, sequence period)
};

// Whose rules apply to overrides (rpm range, fixed column period).
enum class SpinningFamily { Custom, Velodyne, Ouster };

struct SpinningConfig {
    std::vector<LaserSpec> lasers;
    double sequence_period_ns = 0;  // one firing sequence (Velodyne) or column (Ouster)
    double rotation_hz = 10;        // rotor frequency; rpm = 60·rotation_hz
    SpinningFamily family = SpinningFamily::Custom;
};

// Spinning multi-beam pattern (rotor turns clockwise seen from above).
// Pulse k: sequence s = k / L, slot i = k % L → laser l = order[i] (lasers sorted by firing offset,
// ties by index); t = s·period + offset[l]; azimuth = 360°·f_rot·t + az_offset[l] (wrapped to
// [0, 360)); dir = (cos el·cos az, −cos el·sin az, sin el) in FLU.
// Offsets are shifted so the earliest laser fires at t = 0; t_ns is rounded to whole ns.
class SpinningPattern final : public ScanPattern {
  public:
    // Throws ConfigError ("sensor: spinning: …") on an empty laser list, a non-positive period or
    // rotation rate, or a firing offset outside [0, period).
    explicit SpinningPattern(SpinningConfig config);

    std::string kind() const override { return "spinning"; }
    std::uint64_t pulse_count(core::Nanos duration) const override;
    void pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const override;
    double pulse_rate_hz() const override;
    std::uint32_t channels() const override { return static_cast<std::uint32_t>(slots_.size()); }
    std::uint32_t group_size() const override { return channels(); }

    const SpinningConfig& config() const { return config_; }
    // Azimuth advance between consecutive firing sequences: 360°·f_rot·period.
    double azimuth_step_deg() const { return step_deg_; }
    double rpm() const { return 60.0 * config_.rotation_hz; }

  private:
    struct Slot {
        std::uint16_t channel;
        std::int64_t offset_ns;   // rounded firing offset
        double azimuth_base_deg;  // 360·f·offset + az_offset
        double cos_el, sin_el;
        float elevation_deg;
        // Base azimuth wrapped to [0, 360) and cos_el·cos/sin of it: a pulse's direction is the
        // rotor rotation (one sincos per sequence) composed with these, by angle addition.
        double base_wrapped_deg = 0, ecos_base = 0, esin_base = 0;
    };
    std::int64_t time_ns(std::uint64_t k) const;

    SpinningConfig config_;
    std::vector<Slot> slots_;  // in firing order
    double step_deg_ = 0;
};

}  // namespace mirage::sensor
