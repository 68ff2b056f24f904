// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {

// Single-beam airborne scanners. Sensor frame = FLU body; the nominal beam points down (−z).
// The scan angle θ is across track, positive to the right (−y): dir = (0, −sin θ, −cos θ), and is
// what LAS records as scan_angle_deg. Timing: pulse k fires at t = k / prf (rounded to ns).
enum class AirborneKind {
    Sawtooth,  // oscillating mirror, zig-zag: −FOV/2 → +FOV/2 → −FOV/2 at constant speed
    Sine,      // oscillating mirror, θ = FOV/2·sin(2π f t)
    Polygon,   // rotating polygon: unidirectional lines −FOV/2 → +FOV/2, then jump back
    Palmer,    // conical: beam on a cone of half-angle FOV/2 about nadir, azimuth 2π f t
};

std::string to_string(AirborneKind kind);

struct AirborneConfig {
    AirborneKind kind = AirborneKind::Sawtooth;
    double prf_hz = 500e3;
    // Mechanical frequency, Hz: mirror oscillation periods per second (sawtooth, sine: two scan
    // lines per period), polygon revolutions per second (facets lines per revolution), Palmer
    // revolutions per second (one forward and one backward line per revolution).
    double scan_rate_hz = 50;
    double fov_deg = 40;  // full field of view; Palmer: cone half-angle = fov/2
    int facets = 1;       // polygon only
    double tilt_deg = 0;  // the whole pattern pitched forward by this angle (about +y)

    double lines_per_s() const;
};

// Common timing, tilt and bookkeeping; the concrete pattern steers one pulse.
class AirbornePattern : public ScanPattern {
  public:
    explicit AirbornePattern(AirborneConfig config);

    std::uint64_t pulse_count(core::Nanos duration) const override;
    void pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const override;
    double pulse_rate_hz() const override { return config_.prf_hz; }
    std::uint32_t channels() const override { return 1; }
    // Consecutive pulses along a line are coherent: trace them in packets of 16.
    std::uint32_t group_size() const override { return 16; }

    const AirborneConfig& config() const { return config_; }

  protected:
    // Untilted direction, scan angle, scan_direction and edge_of_flight_line of pulse k.
    virtual void steer(std::uint64_t k, PulseSpec& p) const = 0;
    // Continuous cycles of the mechanical frequency at pulse k: k·scan_rate/prf.
    double cycles(std::uint64_t k) const;

    AirborneConfig config_;

  private:
    std::int64_t time_ns(std::uint64_t k) const;
    double period_ns_ = 0;
    double cos_tilt_ = 1, sin_tilt_ = 0;
};

// Throws ConfigError ("sensor: airborne: …") on non-positive rates, fov outside (0, 180)
// (Palmer: (0, 180) full cone), facets < 1 or |tilt| > 60°.
std::shared_ptr<const AirbornePattern> make_airborne_pattern(const AirborneConfig& config);

}  // namespace mirage::sensor
