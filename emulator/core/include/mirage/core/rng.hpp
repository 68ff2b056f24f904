// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace mirage::core {

// Counter-based generator (Philox4x32-10, Salmon et al. 2011): the output is a pure function of
// (seed, pulse, stream), so a pulse draws the same numbers whichever thread renders it.
// Written here although Debian packages Random123 (the reference it is tested against word for
// word): the batched form below vectorises across counters (docs/dependencies.md).
std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> counter,
                                        std::array<std::uint32_t, 2> key);  // defined below

// Random numbers of one pulse (and sub-ray/stream). Cheap to construct; not shared.
class PulseRng {
  public:
    PulseRng(std::uint64_t seed, std::uint64_t pulse, std::uint32_t stream = 0)
        : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
          pulse_(pulse),
          stream_(stream) {}
    // The generator once `used` words of its block 0, drawn already (philox_blocks), are taken:
    // from there it draws what one that drew them itself would.
    PulseRng(std::uint64_t seed, std::uint64_t pulse, std::uint32_t stream,
             const std::array<std::uint32_t, 4>& block0, int used)
        : PulseRng(seed, pulse, stream) {
        buf_ = block0;
        block_ = 1;
        used_ = used;
    }
    // Uniform in (0, 1), never 0 or 1: one 32-bit Philox word u as (u + 0.5)·2⁻³².
    // Counter = {pulse lo, pulse hi, stream, block}; key = seed; 4 uniforms per block.
    double uniform();
    // Standard normal from one uniform by the inverse CDF (Acklam's approximation).
    double normal();

  private:
    std::array<std::uint32_t, 2> key_;
    std::uint64_t pulse_;
    std::uint32_t stream_;
    std::uint32_t block_ = 0;
    std::array<std::uint32_t, 4> buf_{};
    int used_ = 4;
};

// Definitions inline: the pipeline draws a few numbers per pulse, and a call per draw showed in
// its profile.
namespace detail {

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

}  // namespace detail

inline std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> c,
                                               std::array<std::uint32_t, 2> k) {
    for (int round = 0; round < 10; ++round) {
        if (round > 0) {
            k[0] += detail::kWeyl0;
            k[1] += detail::kWeyl1;
        }
        std::uint32_t hi0, lo0, hi1, lo1;
        detail::mul_hi_lo(detail::kMul0, c[0], hi0, lo0);
        detail::mul_hi_lo(detail::kMul1, c[2], hi1, lo1);
        c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
    }
    return c;
}

// 32 random bits per uniform, centred in their bin: (u + ½)·2⁻³² lies in [2⁻³³, 1 − 2⁻³³],
// so the log in the normal's tails is always finite. The resolution (2.3e-10) is far below any
// per-pulse probability; normals reach 6.8 σ at most, which matters only beyond ~1e11 draws.
// One mapping for PulseRng::uniform() and the batched draws.
inline double uniform_of_word(std::uint32_t u) { return (static_cast<double>(u) + 0.5) * 0x1p-32; }

inline double PulseRng::uniform() {
    if (used_ == 4) {
        buf_ = philox4x32({static_cast<std::uint32_t>(pulse_),
                           static_cast<std::uint32_t>(pulse_ >> 32), stream_, block_++},
                          key_);
        used_ = 0;
    }
    const std::uint32_t u = buf_[static_cast<std::size_t>(used_++)];
    return uniform_of_word(u);
}

// Inverse normal CDF (P. J. Acklam's rational approximation, relative error < 1.2e-9): 95 % of
// draws need only two short polynomials, no log or trigonometry, which makes per-pulse noise
// several times cheaper than Box–Muller. Tails use one log and one sqrt.
namespace detail {
inline constexpr double kAcklamA[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                      -2.759285104469687e+02, 1.383577518672690e+02,
                                      -3.066479806614716e+01, 2.506628277459239e+00};
inline constexpr double kAcklamB[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                      -1.556989798598866e+02, 6.680131188771972e+01,
                                      -1.328068155288572e+01};
inline constexpr double kAcklamC[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                      -2.400758277161838e+00, -2.549732539343734e+00,
                                      4.374664141464968e+00,  2.938163982698783e+00};
inline constexpr double kAcklamD[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                      2.445134137142996e+00, 3.754408661907416e+00};
inline constexpr double kAcklamLow = 0.02425;

// The central region, |p − ½| ≤ ½ − kAcklamLow.
inline double acklam_central(double p) {
    const double* a = kAcklamA;
    const double* b = kAcklamB;
    const double q = p - 0.5, r = q * q;
    return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
           (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}
inline bool acklam_is_tail(double p) { return p < kAcklamLow || p > 1.0 - kAcklamLow; }
inline double acklam_tail(double p) {
    const double* c = kAcklamC;
    const double* d = kAcklamD;
    const double q = std::sqrt(-2.0 * std::log(p < kAcklamLow ? p : 1.0 - p));
    const double x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
                     ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    return p < kAcklamLow ? x : -x;
}
}  // namespace detail

inline double inverse_normal_cdf(double p) {
    return detail::acklam_is_tail(p) ? detail::acklam_tail(p) : detail::acklam_central(p);
}

inline double PulseRng::normal() { return inverse_normal_cdf(uniform()); }

// Batched draws for many pulses at once, equal word for word to PulseRng: independent lanes let
// the compiler vectorise what is a long dependency chain per pulse.
//
// Block `block[j]` of pulse `pulse[j]` (stream `stream`, key `seed`): word k of it, the
// (4·block[j] + k)-th uniform PulseRng(seed, pulse[j], stream) draws, goes to words[k][j].
void philox_blocks(std::uint64_t seed, std::uint32_t stream, const std::uint64_t* pulse,
                   const std::uint32_t* block, std::size_t n, std::array<std::uint32_t*, 4> words);
// Standard normals of n words: out[j] = inverse_normal_cdf(uniform_of_word(w[j])).
void normals_of_words(const std::uint32_t* w, std::size_t n, double* out);

}  // namespace mirage::core
