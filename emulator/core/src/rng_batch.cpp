// SPDX-License-Identifier: Apache-2.0
#include <algorithm>

#include "mirage/core/rng.hpp"

namespace mirage::core {

namespace {
constexpr std::size_t kLanes = 8;  // one AVX-512 register of 64-bit products
}

void philox_blocks(std::uint64_t seed, std::uint32_t stream, const std::uint64_t* pulse,
                   const std::uint32_t* block, std::size_t n, std::array<std::uint32_t*, 4> words) {
    const auto k0 = static_cast<std::uint32_t>(seed), k1 = static_cast<std::uint32_t>(seed >> 32);
    for (std::size_t j0 = 0; j0 < n; j0 += kLanes) {
        const std::size_t m = std::min(kLanes, n - j0);
        // Lanes past n repeat lane 0, so the round loop below always runs kLanes wide.
        std::uint32_t c0[kLanes], c1[kLanes], c2[kLanes], c3[kLanes];
        for (std::size_t l = 0; l < kLanes; ++l) {
            const std::size_t j = j0 + (l < m ? l : 0);
            c0[l] = static_cast<std::uint32_t>(pulse[j]);
            c1[l] = static_cast<std::uint32_t>(pulse[j] >> 32);
            c2[l] = stream;
            c3[l] = block[j];
        }
        std::uint32_t key0 = k0, key1 = k1;
        for (int round = 0; round < 10; ++round) {  // as philox4x32(), lane by lane
            if (round > 0) {
                key0 += detail::kWeyl0;
                key1 += detail::kWeyl1;
            }
            for (std::size_t l = 0; l < kLanes; ++l) {
                const std::uint64_t p0 = std::uint64_t{detail::kMul0} * c0[l];
                const std::uint64_t p1 = std::uint64_t{detail::kMul1} * c2[l];
                const auto hi0 = static_cast<std::uint32_t>(p0 >> 32);
                const auto lo0 = static_cast<std::uint32_t>(p0);
                const auto hi1 = static_cast<std::uint32_t>(p1 >> 32);
                const auto lo1 = static_cast<std::uint32_t>(p1);
                const std::uint32_t n0 = hi1 ^ c1[l] ^ key0, n2 = hi0 ^ c3[l] ^ key1;
                c0[l] = n0;
                c1[l] = lo1;
                c2[l] = n2;
                c3[l] = lo0;
            }
        }
        for (std::size_t l = 0; l < m; ++l) {
            words[0][j0 + l] = c0[l];
            words[1][j0 + l] = c1[l];
            words[2][j0 + l] = c2[l];
            words[3][j0 + l] = c3[l];
        }
    }
}

void normals_of_words(const std::uint32_t* w, std::size_t n, double* out) {
    // The central formula for every draw (a loop without branches, vectorised), then the ~5 %
    // in the tails again with their own formula.
    for (std::size_t j = 0; j < n; ++j) out[j] = detail::acklam_central(uniform_of_word(w[j]));
    for (std::size_t j = 0; j < n; ++j) {
        const double p = uniform_of_word(w[j]);
        if (detail::acklam_is_tail(p)) out[j] = detail::acklam_tail(p);
    }
}

}  // namespace mirage::core
