// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>

namespace mirage::core {

// Counter-based generator (Philox4x32-10, Salmon et al. 2011): the output is a pure function of
// (seed, pulse, stream), so a pulse draws the same numbers whichever thread renders it.
// Hand-written: no Debian package provides a counter-based generator for C++.
std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> counter,
                                        std::array<std::uint32_t, 2> key);

// Random numbers of one pulse (and sub-ray/stream). Cheap to construct; not shared.
class PulseRng {
  public:
    PulseRng(std::uint64_t seed, std::uint64_t pulse, std::uint32_t stream = 0)
        : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
          pulse_(pulse),
          stream_(stream) {}
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

}  // namespace mirage::core
