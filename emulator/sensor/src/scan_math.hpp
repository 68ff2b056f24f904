// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cmath>
#include <cstdint>

#include "mirage/core/rounding.hpp"

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

// A laser firing every period_ns: pulse k at k·period rounded to the ns, and the pulses fired
// in [0, duration_ns) (the airborne patterns and the staring laser).
inline std::int64_t fixed_rate_time_ns(std::uint64_t k, double period_ns) {
    return static_cast<std::int64_t>(core::round_half_away(static_cast<double>(k) * period_ns));
}
inline std::uint64_t fixed_rate_count(std::int64_t duration_ns, double period_ns) {
    const double n = static_cast<double>(duration_ns) / period_ns;
    const std::uint64_t hi = static_cast<std::uint64_t>(n > 0.0 ? n : 0.0) + 2;
    return count_before(duration_ns, hi,
                        [&](std::uint64_t k) { return fixed_rate_time_ns(k, period_ns); });
}

// sin and cos of a scan angle, |x| ≤ π/4 by Taylor series (airborne mirrors swing ±10–40°):
// the first omitted terms are below 5e-17 there, and the direction they build is stored as
// float. Two libm calls per pulse were the largest item of the airborne pulse generator.
// Larger angles fall back to the library.
inline void small_sincos(double x, double& s, double& c) {
    if (!(std::abs(x) <= 0.7853981633974483)) {
        s = std::sin(x);
        c = std::cos(x);
        return;
    }
    // Taylor coefficients, highest power first (Horner).
    constexpr double kSin[] = {
        -1.0 / 1307674368000, 1.0 / 6227020800, -1.0 / 39916800, 1.0 / 362880,
        -1.0 / 5040,          1.0 / 120,        -1.0 / 6,        1.0};
    constexpr double kCos[] = {1.0 / 20922789888000,
                               -1.0 / 87178291200,
                               1.0 / 479001600,
                               -1.0 / 3628800,
                               1.0 / 40320,
                               -1.0 / 720,
                               1.0 / 24,
                               -0.5,
                               1.0};
    const double x2 = x * x;
    double ps = 0, pc = 0;
    for (double k : kSin) ps = ps * x2 + k;
    for (double k : kCos) pc = pc * x2 + k;
    s = x * ps;
    c = pc;
}

// Angle in [0, 360).
inline double wrap_deg(double deg) {
    // fmod returns |deg| < 360 unchanged: skip the library call for the usual case.
    if (deg >= 0.0 && deg < 360.0) return deg;
    double a = std::fmod(deg, 360.0);
    if (a < 0) a += 360.0;
    if (a >= 360.0) a -= 360.0;
    return a;
}

}  // namespace mirage::sensor::detail
