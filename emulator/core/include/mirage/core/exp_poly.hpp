// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace mirage::core {

// e^x within 2 ulp of std::exp, written inline without branches so a loop over many values
// vectorises (std::exp is a library call per value; the pipeline needs τ² = e^(−2αR) per
// sub-ray). x = k·ln 2 + r with |r| ≤ ln 2 / 2 (Cody–Waite: k·ln2_hi is exact for |k| < 2¹¹),
// e^r by its Taylor series to r¹² (truncation < 2e-16 relative), times 2^k through the exponent
// bits. Below −708 the result is 0 (e^x would be subnormal), above 709 +inf; NaN stays NaN.
inline double exp_poly(double x) {
    constexpr double kLog2e = 1.4426950408889634;
    constexpr double kLn2Hi = 6.93147180369123816490e-01;  // 0x3fe62e42fee00000
    constexpr double kLn2Lo = 1.90821492927058770002e-10;
    const double xc = std::clamp(x, -708.0, 709.0);
    const double k = std::nearbyint(xc * kLog2e);
    const double r = (xc - k * kLn2Hi) - k * kLn2Lo;
    // e^r = 1 + (r + r²·q(r)), q = 1/2! + r/3! + … + r¹⁰/12!: the polynomial's rounding stays in
    // the small r²·q and 1 is added last, so the result is within 2 ulp with or without fused
    // multiply-adds (the ASan build has none).
    double q = 1.0 / 479001600.0;  // 1/12!
    q = q * r + 1.0 / 39916800.0;
    q = q * r + 1.0 / 3628800.0;
    q = q * r + 1.0 / 362880.0;
    q = q * r + 1.0 / 40320.0;
    q = q * r + 1.0 / 5040.0;
    q = q * r + 1.0 / 720.0;
    q = q * r + 1.0 / 120.0;
    q = q * r + 1.0 / 24.0;
    q = q * r + 1.0 / 6.0;
    q = q * r + 0.5;
    const double p = 1.0 + (r + r * r * q);
    // 2^k for k in [−1022, 1023]: the biased exponent k + 1023 in bits 52–62 (k through int32:
    // AVX2 turns doubles into 32-bit integers four at a time, into 64-bit ones not at all).
    const auto bits = static_cast<std::uint64_t>(static_cast<std::int32_t>(k) + 1023) << 52;
    const double v = p * std::bit_cast<double>(bits);
    return x < -708.0 ? 0.0 : (x > 709.0 ? HUGE_VAL : (x == x ? v : x));
}

}  // namespace mirage::core
