// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/rng.hpp"

#include <cmath>
#include <numbers>

namespace mirage::core {
namespace {

// Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy as 1, 2, 3" (SC 2011), §4:
// Philox4x32 round multipliers and the Weyl-sequence key increments.
constexpr std::uint32_t kMul0 = 0xD2511F53u;
constexpr std::uint32_t kMul1 = 0xCD9E8D57u;
constexpr std::uint32_t kWeyl0 = 0x9E3779B9u;
constexpr std::uint32_t kWeyl1 = 0xBB67AE85u;

inline void mul_hi_lo(std::uint32_t a, std::uint32_t b, std::uint32_t& hi, std::uint32_t& lo) {
    const std::uint64_t p = static_cast<std::uint64_t>(a) * b;
    hi = static_cast<std::uint32_t>(p >> 32);
    lo = static_cast<std::uint32_t>(p);
}

}  // namespace

std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> c,
                                        std::array<std::uint32_t, 2> k) {
    for (int round = 0; round < 10; ++round) {
        if (round > 0) {
            k[0] += kWeyl0;
            k[1] += kWeyl1;
        }
        std::uint32_t hi0, lo0, hi1, lo1;
        mul_hi_lo(kMul0, c[0], hi0, lo0);
        mul_hi_lo(kMul1, c[2], hi1, lo1);
        c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
    }
    return c;
}

// 32 random bits per uniform, centred in their bin: (u + ½)·2⁻³² lies in [2⁻³³, 1 − 2⁻³³],
// so log(u) in Box–Muller is always finite. The resolution (2.3e-10) is far below any
// per-pulse probability; normals reach 6.8 σ at most, which matters only beyond ~1e11 draws.
double PulseRng::uniform() {
    if (used_ == 4) {
        buf_ = philox4x32({static_cast<std::uint32_t>(pulse_),
                           static_cast<std::uint32_t>(pulse_ >> 32), stream_, block_++},
                          key_);
        used_ = 0;
    }
    const std::uint32_t u = buf_[static_cast<std::size_t>(used_++)];
    return (static_cast<double>(u) + 0.5) * 0x1p-32;
}

double PulseRng::normal() {
    if (has_spare_) {
        has_spare_ = false;
        return spare_;
    }
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    const double theta = 2.0 * std::numbers::pi * uniform();
    spare_ = r * std::sin(theta);
    has_spare_ = true;
    return r * std::cos(theta);
}

}  // namespace mirage::core
