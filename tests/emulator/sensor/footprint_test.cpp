// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {
namespace {

TEST(Footprint, single_sample_is_the_centred_ray_with_all_the_weight) {
    for (auto profile : {BeamProfile::Gaussian, BeamProfile::TopHat}) {
        const auto f = footprint(1, profile, 3e-3);
        ASSERT_EQ(f.size(), 1u);
        EXPECT_EQ(f[0].dx, 0.0f);
        EXPECT_EQ(f[0].dy, 0.0f);
        EXPECT_EQ(f[0].weight, 1.0f);
    }
}

TEST(Footprint, hex_rings_sum_to_one_are_symmetric_and_stay_inside_the_beam) {
    const double div = 3e-3;
    for (int n : {7, 19, 37, 61}) {
        for (auto profile : {BeamProfile::Gaussian, BeamProfile::TopHat}) {
            const auto f = footprint(n, profile, div);
            ASSERT_EQ(f.size(), std::size_t(n));
            double sum = 0, mx = 0, my = 0, wx = 0, wy = 0, rmax = 0;
            for (const auto& s : f) {
                sum += s.weight;
                mx += s.dx;
                my += s.dy;
                wx += s.weight * s.dx;
                wy += s.weight * s.dy;
                rmax = std::max(rmax, std::hypot(double(s.dx), double(s.dy)));
                EXPECT_GT(s.weight, 0.0f);
            }
            EXPECT_NEAR(sum, 1.0, 1e-6) << n;
            EXPECT_NEAR(mx / n, 0.0, 1e-9) << n;
            EXPECT_NEAR(my / n, 0.0, 1e-9) << n;
            EXPECT_NEAR(wx, 0.0, 1e-9) << n;
            EXPECT_NEAR(wy, 0.0, 1e-9) << n;
            EXPECT_NEAR(rmax, div / 2, 1e-9) << n;  // outer ring on the beam radius
        }
    }
}

TEST(Footprint, weights_follow_the_profile_and_cell_areas) {
    // n = 7, k = 1: centre cell a disc of radius Δ/2 (area π/4), ring cells share the annulus
    // [Δ/2, Δ] (area 3π/4 over 6). Top-hat: weights ∝ area; Gaussian: × exp(−2) on the ring.
    const auto th = footprint(7, BeamProfile::TopHat, 2e-3);
    const double ring = (3.0 / 4.0) / 6.0, centre = 1.0 / 4.0;
    EXPECT_NEAR(th[0].weight, centre / (centre + 6 * ring), 1e-6);
    EXPECT_NEAR(th[1].weight, ring / (centre + 6 * ring), 1e-6);
    const auto g = footprint(7, BeamProfile::Gaussian, 2e-3);
    const double gr = ring * std::exp(-2.0);
    EXPECT_NEAR(g[0].weight, centre / (centre + 6 * gr), 1e-6);
    EXPECT_NEAR(g[3].weight, gr / (centre + 6 * gr), 1e-6);
    // 19: rings at Δ and 2Δ with 6 and 12 samples; Gaussian weight falls outward.
    const auto g19 = footprint(19, BeamProfile::Gaussian, 2e-3);
    EXPECT_GT(g19[0].weight, g19[1].weight);
    EXPECT_GT(g19[1].weight, g19[7].weight);
    EXPECT_NEAR(std::hypot(g19[1].dx, g19[1].dy), 0.5e-3, 1e-9);
    EXPECT_NEAR(std::hypot(g19[7].dx, g19[7].dy), 1.0e-3, 1e-9);
}

TEST(Footprint, is_deterministic) {
    const auto a = footprint(37, BeamProfile::Gaussian, 1e-3);
    const auto b = footprint(37, BeamProfile::Gaussian, 1e-3);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].dx, b[i].dx);
        EXPECT_EQ(a[i].dy, b[i].dy);
        EXPECT_EQ(a[i].weight, b[i].weight);
    }
}

TEST(Footprint, zero_divergence_collapses_onto_the_axis) {
    const auto f = footprint(7, BeamProfile::Gaussian, 0.0);
    double sum = 0;
    for (const auto& s : f) {
        EXPECT_EQ(s.dx, 0.0f);
        EXPECT_EQ(s.dy, 0.0f);
        sum += s.weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
}

TEST(Footprint, rejects_counts_that_are_not_hexagonal) {
    for (int n : {0, -1, 2, 5, 8, 18, 20}) {
        EXPECT_FALSE(is_hex_count(n)) << n;
        EXPECT_THROW(footprint(n, BeamProfile::Gaussian, 1e-3), ConfigError) << n;
    }
    for (int n : {1, 7, 19, 37, 61, 91}) EXPECT_TRUE(is_hex_count(n)) << n;
    try {
        footprint(5, BeamProfile::TopHat, 1e-3);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("5 is not a hexagonal count (1, 7, 19, 37"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(footprint(7, BeamProfile::TopHat, -1e-3), ConfigError);
}

}  // namespace
}  // namespace mirage::sensor
