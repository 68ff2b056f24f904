// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {

// A laser that fires at a fixed rate along one direction: what a flash array stares with (a
// frame per pulse; docs/photon-counting.md §3). Pulse k fires at k / prf (rounded to ns), along
// nadir (−z) for an airborne sensor, else forward (+x); scan angle and azimuth are 0.
class StaringPattern final : public ScanPattern {
  public:
    StaringPattern(double prf_hz, bool nadir);
    std::string kind() const override { return "staring"; }
    std::uint64_t pulse_count(core::Nanos duration) const override;
    void pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const override;
    double pulse_rate_hz() const override { return prf_hz_; }
    std::uint32_t channels() const override { return 1; }
    bool nadir() const { return nadir_; }

  private:
    double prf_hz_, period_ns_;
    bool nadir_;
};

}  // namespace mirage::sensor
