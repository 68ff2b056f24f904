// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/rng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

using namespace mirage::core;

using Block = std::array<std::uint32_t, 4>;

// Known-answer vectors from Random123's kat_vectors (philox4x32 10 rounds).
TEST(Philox, zero_counter_and_key) {
    EXPECT_EQ(philox4x32({0, 0, 0, 0}, {0, 0}),
              (Block{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
}

TEST(Philox, all_ones_counter_and_key) {
    EXPECT_EQ(philox4x32({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                         {0xffffffffu, 0xffffffffu}),
              (Block{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
}

TEST(Philox, pi_digits_counter_and_key) {
    EXPECT_EQ(philox4x32({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
                         {0xa4093822u, 0x299f31d0u}),
              (Block{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

TEST(PulseRng, uniforms_are_philox_words_of_pulse_stream_block) {
    const std::uint64_t seed = 0x0123456789abcdefULL, pulse = 0x0000000500000007ULL;
    PulseRng rng(seed, pulse, 9);
    for (std::uint32_t block = 0; block < 3; ++block) {
        const Block w = philox4x32({7u, 5u, 9u, block}, {0x89abcdefu, 0x01234567u});
        for (std::uint32_t word : w) {
            EXPECT_EQ(rng.uniform(), (static_cast<double>(word) + 0.5) / 4294967296.0);
        }
    }
}

TEST(PulseRng, uniform_stays_strictly_inside_zero_one_with_mean_half) {
    double lo = 1, hi = 0, sum = 0;
    constexpr int kN = 1'000'000;
    for (int p = 0; p < kN / 100; ++p) {
        PulseRng rng(1, static_cast<std::uint64_t>(p));
        for (int i = 0; i < 100; ++i) {
            const double u = rng.uniform();
            lo = std::min(lo, u);
            hi = std::max(hi, u);
            sum += u;
        }
    }
    EXPECT_GT(lo, 0.0);
    EXPECT_LT(hi, 1.0);
    EXPECT_NEAR(sum / kN, 0.5, 0.002);
    // The extreme words map to 2^-33 and 1 - 2^-33, both inside (0, 1).
    EXPECT_GT((0.0 + 0.5) / 4294967296.0, 0.0);
    EXPECT_LT((4294967295.0 + 0.5) / 4294967296.0, 1.0);
}

TEST(PulseRng, normals_have_zero_mean_and_unit_variance) {
    constexpr int kN = 1'000'000;
    double sum = 0, sum2 = 0, sum4 = 0;
    PulseRng rng(2024, 77, 3);
    for (int i = 0; i < kN; ++i) {
        const double x = rng.normal();
        ASSERT_TRUE(std::isfinite(x));
        sum += x;
        sum2 += x * x;
        sum4 += x * x * x * x;
    }
    const double mean = sum / kN, var = sum2 / kN - mean * mean, kurt = sum4 / kN;
    std::printf("1e6 normals: mean %.5f, variance %.5f, E[x^4] %.4f\n", mean, var, kurt);
    EXPECT_NEAR(mean, 0.0, 0.005);
    EXPECT_NEAR(var, 1.0, 0.01);
    EXPECT_NEAR(kurt, 3.0, 0.05);  // Gaussian tails, not just the first two moments
}

TEST(PulseRng, same_seed_pulse_stream_repeats_exactly) {
    PulseRng a(99, 123456789, 2), b(99, 123456789, 2);
    for (int i = 0; i < 1000; ++i) {
        ASSERT_EQ(a.uniform(), b.uniform());
        ASSERT_EQ(a.normal(), b.normal());
    }
}

TEST(PulseRng, different_streams_pulses_and_seeds_differ) {
    const auto first8 = [](PulseRng r) {
        std::array<double, 8> v{};
        for (double& x : v) x = r.uniform();
        return v;
    };
    const auto base = first8(PulseRng(5, 1000, 0));
    EXPECT_NE(base, first8(PulseRng(5, 1000, 1)));
    EXPECT_NE(base, first8(PulseRng(5, 1001, 0)));
    EXPECT_NE(base, first8(PulseRng(6, 1000, 0)));
    EXPECT_NE(base, first8(PulseRng(5 + (1ULL << 32), 1000, 0)));  // high seed bits count
    EXPECT_NE(base, first8(PulseRng(5, 1000 + (1ULL << 32), 0)));  // high pulse bits count
    // Streams are uncorrelated: correlation of 1e5 paired uniforms is ~0.
    double sxy = 0;
    for (std::uint64_t p = 0; p < 100'000; ++p) {
        PulseRng a(5, p, 0), b(5, p, 1);
        sxy += (a.uniform() - 0.5) * (b.uniform() - 0.5);
    }
    EXPECT_NEAR(sxy / 100'000 * 12.0, 0.0, 0.02);
}

// The batched draws the pipeline makes are PulseRng's, word for word and normal for normal,
// including counts that are not a multiple of the vector width and words in both tails.
TEST(PhiloxBlocks, equal_pulse_rng_draws_for_any_pulse_block_and_count) {
    const std::uint64_t seed = 0xfeedbeef12345678ULL;
    for (std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{8}, std::size_t{29}}) {
        std::vector<std::uint64_t> pulse(n);
        std::vector<std::uint32_t> block(n);
        for (std::size_t j = 0; j < n; ++j) {
            pulse[j] = 0x1'0000'0000ULL * (j % 3) + 1000 * j + 17;
            block[j] = static_cast<std::uint32_t>(j % 4);
        }
        std::array<std::vector<std::uint32_t>, 4> w;
        for (auto& v : w) v.assign(n, 0);
        philox_blocks(seed, 2, pulse.data(), block.data(), n,
                      {w[0].data(), w[1].data(), w[2].data(), w[3].data()});
        std::array<std::vector<double>, 4> z;
        for (std::size_t k = 0; k < 4; ++k) {
            z[k].assign(n, 0.0);
            normals_of_words(w[k].data(), n, z[k].data());
        }
        for (std::size_t j = 0; j < n; ++j) {
            PulseRng u(seed, pulse[j], 2), g(seed, pulse[j], 2);
            for (std::uint32_t skip = 0; skip < 4 * block[j]; ++skip) {
                u.uniform();
                g.normal();
            }
            for (std::size_t k = 0; k < 4; ++k) {
                EXPECT_EQ(uniform_of_word(w[k][j]), u.uniform()) << "n " << n << " j " << j;
                EXPECT_EQ(z[k][j], g.normal()) << "n " << n << " j " << j;
            }
        }
    }
}

TEST(PhiloxBlocks, normals_of_words_use_the_tail_formula_in_both_tails) {
    // Words at p = 0.001, 0.5 and 0.999: Φ⁻¹ = −3.0902, 0, 3.0902 (to the approximation's 1e-9).
    const std::uint32_t w[3] = {4294967u, 2147483647u, 4290672328u};
    double z[3] = {};
    normals_of_words(w, 3, z);
    EXPECT_NEAR(z[0], -3.090232306, 1e-6);
    EXPECT_NEAR(z[1], 0.0, 1e-9);
    EXPECT_NEAR(z[2], 3.090232306, 1e-6);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(z[k], inverse_normal_cdf(uniform_of_word(w[k])));
}
