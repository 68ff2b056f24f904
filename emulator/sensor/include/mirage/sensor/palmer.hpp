// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "mirage/sensor/airborne.hpp"

namespace mirage::sensor {

// Palmer (conical) scanner: the beam lies on a cone of half-angle c = F/2 about nadir and turns
// clockwise seen from above: φ = 2π·f·t, dir = (sin c·cos φ, −sin c·sin φ, −cos c), so it points
// forward at φ = 0, right at 90°, backward at 180°. Each revolution draws a forward line
// (left → right, scan_direction 1) and a backward line (right → left); lines change at the
// extreme left/right, line = ⌊2x + ½⌋ with x = f·t. LAS scan angle = across-track projection
// atan2(sin c·sin φ, cos c) (+ right); the off-nadir angle is always c.
class PalmerPattern final : public AirbornePattern {
  public:
    explicit PalmerPattern(AirborneConfig config);
    std::string kind() const override { return "palmer"; }

  protected:
    void steer(std::uint64_t k, PulseSpec& p) const override;
};

}  // namespace mirage::sensor
