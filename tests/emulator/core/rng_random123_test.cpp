// SPDX-License-Identifier: Apache-2.0
// Mirage's Philox4x32-10 against the reference implementation, Random123 (Debian
// librandom123-dev), word for word: the scalar generator and the batched, vectorised one the
// pipeline uses. Why Mirage keeps its own: docs/dependencies.md.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "mirage/core/rng.hpp"
// After Mirage's header: Random123 defines a function-like macro of the same name.
#include <Random123/philox.h>
#undef philox4x32

namespace mirage::core {
namespace {

using Block = std::array<std::uint32_t, 4>;

Block reference(const Block& c, std::uint32_t k0, std::uint32_t k1) {
    r123::Philox4x32 g;  // 10 rounds
    const r123::Philox4x32::ctr_type ctr = {{c[0], c[1], c[2], c[3]}};
    const r123::Philox4x32::key_type key = {{k0, k1}};
    const auto out = g(ctr, key);
    return {out[0], out[1], out[2], out[3]};
}

// A cheap stream of test inputs (not the generator under test).
std::uint32_t next(std::uint64_t& s) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::uint32_t>(s >> 32);
}

TEST(PhiloxRandom123, scalar_generator_equals_the_reference_on_100000_counters_and_keys) {
    std::uint64_t s = 42;
    for (int i = 0; i < 100'000; ++i) {
        const Block c{next(s), next(s), next(s), next(s)};
        const std::uint32_t k0 = next(s), k1 = next(s);
        ASSERT_EQ(philox4x32(c, {k0, k1}), reference(c, k0, k1)) << "input " << i;
    }
}

TEST(PhiloxRandom123, batched_blocks_equal_the_reference_for_the_pipelines_counters) {
    // Counter = {pulse lo, pulse hi, stream, block}, key = seed (PulseRng's layout).
    constexpr std::size_t n = 4099;  // not a multiple of any vector width
    std::uint64_t s = 7;
    std::vector<std::uint64_t> pulse(n);
    std::vector<std::uint32_t> block(n);
    for (std::size_t j = 0; j < n; ++j) {
        pulse[j] = (std::uint64_t{next(s)} << 32) | next(s);
        block[j] = next(s) % 8;
    }
    const std::uint64_t seed = 0x0123456789abcdefULL;
    const std::uint32_t stream = 3;
    std::array<std::vector<std::uint32_t>, 4> w;
    for (auto& v : w) v.resize(n);
    philox_blocks(seed, stream, pulse.data(), block.data(), n,
                  {w[0].data(), w[1].data(), w[2].data(), w[3].data()});
    for (std::size_t j = 0; j < n; ++j) {
        const Block ref = reference({static_cast<std::uint32_t>(pulse[j]),
                                     static_cast<std::uint32_t>(pulse[j] >> 32), stream, block[j]},
                                    static_cast<std::uint32_t>(seed),
                                    static_cast<std::uint32_t>(seed >> 32));
        ASSERT_EQ((Block{w[0][j], w[1][j], w[2][j], w[3][j]}), ref) << "lane " << j;
    }
}

}  // namespace
}  // namespace mirage::core
