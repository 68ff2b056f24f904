// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "mirage/sensor/airborne.hpp"

namespace mirage::sensor {

// Rotating polygon: each facet sweeps one line −F/2 → +F/2 at constant speed, then the next facet
// starts again at −F/2. lines/s = facets × revolutions/s; x = lines/s · t, line = ⌊x⌋,
// θ = −F/2 + F·frac(x). The whole facet period is used (no dead time between lines).
class PolygonPattern final : public AirbornePattern {
  public:
    explicit PolygonPattern(AirborneConfig config);
    std::string kind() const override { return "polygon"; }

  protected:
    void steer(std::uint64_t k, PulseSpec& p) const override;

  private:
    double lines(std::uint64_t k) const;  // continuous scan lines at pulse k
};

}  // namespace mirage::sensor
