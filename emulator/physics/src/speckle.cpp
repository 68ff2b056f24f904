// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/speckle.hpp"

#include <cmath>

namespace mirage::physics {

double speckle_factor(core::PulseRng& rng, double m) {
    const double d = m - 1.0 / 3.0, c = 1 / std::sqrt(9 * d);
    for (;;) {
        const double x = rng.normal(), t = 1 + c * x;
        if (t <= 0) continue;
        const double v = t * t * t, u = rng.uniform();
        if (std::log(u) < 0.5 * x * x + d - d * v + d * std::log(v)) return d * v / m;
    }
}

}  // namespace mirage::physics
