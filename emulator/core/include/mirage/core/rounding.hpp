// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>

namespace mirage::core {

// Nearest integer, halfway cases away from zero: the value of std::round / std::llround, without
// the library call they compile to (a few per LAS point showed in the writer's profile), and
// without a branch (whether a value rounds up is a coin toss the predictor loses). Adding the
// largest double below ½ and truncating is exact: a sum that rounds up to the next integer does
// so only when v's fraction is ≥ ½ (or v is already an integer beyond 2⁵², where the sum is v).
inline double round_half_away(double v) {
    return std::trunc(v + std::copysign(0.49999999999999994, v));
}

}  // namespace mirage::core
