// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <bit>
#include <cstdint>

namespace mirage::core {

// ln x for positive, normal, finite x, within 2 ulp of std::log; inline and without branches so
// a loop over many values vectorises (std::log is a library call per value; the pipeline maps
// every point's photo-electrons to intensity through it). Other inputs give an unspecified
// finite or NaN result: callers select them away. x = 2^e·m with m in [√½, √2); with
// s = (m − 1)/(m + 1), ln m = 2·atanh s = 2(s + s³/3 + s⁵/5 + …), |s| ≤ 0.172, summed to s²³
// (the next term is below 1e-18 relative); e·ln 2 in two parts (Cody–Waite) keeps it exact.
inline double log_poly(double x) {
    constexpr double kLn2Hi = 6.93147180369123816490e-01;  // 0x3fe62e42fee00000
    constexpr double kLn2Lo = 1.90821492927058770002e-10;
    constexpr double kSqrt2 = 1.4142135623730951;
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const double m1 = std::bit_cast<double>((bits & 0x000F'FFFF'FFFF'FFFFull) |
                                            0x3FF0'0000'0000'0000ull);  // in [1, 2)
    // The exponent through int32: AVX2 turns 32-bit integers into doubles four at a time, 64-bit
    // ones not at all.
    const double e1 = static_cast<double>(static_cast<std::int32_t>(bits >> 52) - 1023);
    const bool high = m1 > kSqrt2;
    const double m = high ? 0.5 * m1 : m1;
    const double e = high ? e1 + 1.0 : e1;
    const double s = (m - 1.0) / (m + 1.0), s2 = s * s;
    double p = 1.0 / 23.0;
    p = p * s2 + 1.0 / 21.0;
    p = p * s2 + 1.0 / 19.0;
    p = p * s2 + 1.0 / 17.0;
    p = p * s2 + 1.0 / 15.0;
    p = p * s2 + 1.0 / 13.0;
    p = p * s2 + 1.0 / 11.0;
    p = p * s2 + 1.0 / 9.0;
    p = p * s2 + 1.0 / 7.0;
    p = p * s2 + 1.0 / 5.0;
    p = p * s2 + 1.0 / 3.0;
    // 2s + 2s·s²·p: the leading term added last keeps the rounding error of the tail small.
    const double ln_m = 2.0 * s + 2.0 * s * (s2 * p);
    return e * kLn2Hi + (ln_m + e * kLn2Lo);
}

}  // namespace mirage::core
