// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "mirage/sensor/airborne.hpp"

namespace mirage::sensor {

// Oscillating mirror, across track. With x = f·t (mirror cycles) and phase p = frac(x):
//   sawtooth (zig-zag): θ = −F/2 + 2F·p for p < ½ (scan_direction 1), F/2 − 2F·(p − ½) after;
//                       line = ⌊2x⌋, turning at ±F/2;
//   sine:               θ = F/2·sin(2πx), scan_direction 1 while cos(2πx) > 0, line = ⌊2x + ½⌋.
// edge_of_flight_line = 1 on the last pulse of each line. Kind Sawtooth or Sine.
class OscillatingMirrorPattern final : public AirbornePattern {
  public:
    explicit OscillatingMirrorPattern(AirborneConfig config);
    std::string kind() const override;

  protected:
    void steer(std::uint64_t k, PulseSpec& p) const override;

  private:
    double line_of(std::uint64_t k) const;
};

}  // namespace mirage::sensor
