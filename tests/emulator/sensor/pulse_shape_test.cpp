// SPDX-License-Identifier: Apache-2.0
// The pulse's temporal shape (docs/time-resolved.md §4) against closed forms: unit area, the
// Gaussian's σ = FWHM / 2.3548, a triangle's moments, and the two-echo resolution limit.
#include "mirage/sensor/pulse_shape.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::sensor {
namespace {

// ∫ t^k s(t) dt by the midpoint rule on n steps over the support.
double moment(const PulseShape& s, int k, int n = 200000) {
    const double h = (s.end_ns() - s.begin_ns()) / n;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double t = s.begin_ns() + (i + 0.5) * h;
        sum += std::pow(t, k) * s(t);
    }
    return sum * h;
}

// Local maxima of two equal echoes Δt apart, sampled every 1 ps.
int maxima_of_two_echoes(const PulseShape& s, double dt_ns) {
    const double step = 0.001;
    auto w = [&](double t) { return s(t) + s(t - dt_ns); };
    int count = 0;
    for (double t = s.begin_ns(); t < s.end_ns() + dt_ns; t += step)
        if (w(t) > w(t - step) && w(t) >= w(t + step)) ++count;
    return count;
}

TEST(PulseShape, gaussian_has_unit_area_its_fwhm_and_sigma) {
    const auto s = PulseShape::gaussian(4.0, "test");
    EXPECT_NEAR(s.sigma_ns(), 4.0 / 2.3548200450309493, 1e-12);
    EXPECT_NEAR(moment(s, 0), 1.0, 1e-9);
    EXPECT_NEAR(moment(s, 1), 0.0, 1e-9);
    EXPECT_NEAR(std::sqrt(moment(s, 2)), s.sigma_ns(), 1e-6);
    EXPECT_NEAR(s(2.0) / s(0.0), 0.5, 1e-12);  // half the peak at ±FWHM/2
    EXPECT_NEAR(s(-2.0) / s(0.0), 0.5, 1e-12);
    EXPECT_EQ(s(s.end_ns() + 1e-9), 0.0);
}

TEST(PulseShape, two_equal_echoes_show_two_maxima_only_beyond_two_sigma) {
    // Two equal Gaussian echoes have two maxima exactly when Δt > 2σ, i.e. ΔR > c·σ.
    const auto s = PulseShape::gaussian(4.0, "test");
    const double limit = 2 * s.sigma_ns();
    EXPECT_EQ(maxima_of_two_echoes(s, 0.97 * limit), 1);
    EXPECT_EQ(maxima_of_two_echoes(s, 1.03 * limit), 2);
}

TEST(PulseShape, tabulated_triangle_is_centred_on_its_centroid_with_unit_area) {
    // An asymmetric triangle on [0, 3] peaking at 1: centroid 4/3, variance (a²+b²+c²−ab−ac−bc)/18
    // = 7/18 for vertices 0, 1, 3; half-maximum crossings at 0.5 and 2, FWHM 1.5.
    const auto s = PulseShape::tabulated({0, 1, 3}, {0, 5, 0}, "tri");
    EXPECT_NEAR(s.begin_ns(), -4.0 / 3.0, 1e-12);
    EXPECT_NEAR(s.end_ns(), 3.0 - 4.0 / 3.0, 1e-12);
    EXPECT_NEAR(s.sigma_ns(), std::sqrt(7.0 / 18.0), 1e-12);
    EXPECT_NEAR(s.fwhm_ns(), 1.5, 1e-12);
    EXPECT_NEAR(moment(s, 0), 1.0, 1e-8);
    EXPECT_NEAR(moment(s, 1), 0.0, 1e-8);
    EXPECT_NEAR(s(1.0 - 4.0 / 3.0), 2.0 / 3.0, 1e-12);  // peak of a unit-area triangle of base 3
}

TEST(PulseShape, impossible_shapes_are_config_errors_naming_the_input) {
    auto error_of = [](auto make) {
        try {
            make();
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error_of([] { PulseShape::gaussian(0.0, "s.yaml: pulse"); }),
              "pulse shape 's.yaml: pulse': fwhm_ns must be a positive number of ns");
    EXPECT_NE(error_of([] { PulseShape::gaussian(std::nan(""), "x"); }), "no error");
    EXPECT_EQ(error_of([] {
                  PulseShape::tabulated({0, 1, 1}, {0, 1, 0}, "p.csv");
              }),
              "pulse shape 'p.csv': sample 2: times must increase strictly");
    EXPECT_EQ(error_of([] {
                  PulseShape::tabulated({0, 1}, {1, -1}, "p.csv");
              }),
              "pulse shape 'p.csv': sample 1: power must be finite and >= 0");
    EXPECT_EQ(error_of([] {
                  PulseShape::tabulated({0, 1}, {0, 0}, "p.csv");
              }),
              "pulse shape 'p.csv': the shape has no area");
    EXPECT_EQ(error_of([] { PulseShape::tabulated({0}, {1}, "p.csv"); }),
              "pulse shape 'p.csv': needs at least 2 samples, one power per time");
}

}  // namespace
}  // namespace mirage::sensor
