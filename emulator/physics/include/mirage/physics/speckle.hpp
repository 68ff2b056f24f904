// SPDX-License-Identifier: Apache-2.0
// Speckle (docs/time-resolved.md §6): the energy a rough surface returns into a finite aperture
// is Gamma-distributed with M speckle cells (sensor::speckle_cells), mean unchanged, contrast
// 1/√M.
#pragma once
#include "mirage/core/rng.hpp"

namespace mirage::physics {

// One factor g ~ Gamma(shape M, scale 1/M) (mean 1, variance 1/M) from `rng`, M ≥ 1
// (Marsaglia & Tsang 2000, which takes a normal and a uniform per try).
double speckle_factor(core::PulseRng& rng, double m);

}  // namespace mirage::physics
