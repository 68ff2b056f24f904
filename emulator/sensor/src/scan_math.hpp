// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <cstdint>

namespace mirage::sensor::detail {

// Number of pulses k in [0, hi) with t(k) < limit_ns, for a non-decreasing t (binary search, so
// pulse_count agrees exactly with the times pulses() hands out).
template <class TimeOf>
std::uint64_t count_before(std::int64_t limit_ns, std::uint64_t hi, TimeOf t) {
    if (limit_ns <= 0) return 0;
    std::uint64_t lo = 0;  // invariant: t(k) < limit for k < lo, t(k) ≥ limit for k ≥ hi
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (t(mid) < limit_ns) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Angle in [0, 360).
inline double wrap_deg(double deg) {
    double a = std::fmod(deg, 360.0);
    if (a < 0) a += 360.0;
    if (a >= 360.0) a -= 360.0;
    return a;
}

}  // namespace mirage::sensor::detail
