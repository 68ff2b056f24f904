// SPDX-License-Identifier: Apache-2.0
// Dead reckoning against closed forms and an independent integration (docs/dis.md §2): R1 and R2
// against Simpson's rule over Rodrigues' rotation, across the series' switch; a body turning
// at a constant rate with a constant body velocity flies a circle of radius V/ω; the world
// algorithms are P0 + V·Δt (+ ½·A·Δt²); the body ones against a Runge–Kutta integration.
#include "mirage/dis/dead_reckoning.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "dis_fixtures.hpp"

namespace mirage::dis {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Rodrigues' formula written out on its own (the unit axis and the angle).
Matrix3d rodrigues(const Vector3d& w, double t) {
    const double n = w.norm();
    if (n == 0.0) return Matrix3d::Identity();
    return Eigen::AngleAxisd(n * t, w / n).toRotationMatrix();
}

// ∫₀ᵀ exp([ω]×τ)·τ^power dτ by Simpson's rule.
Matrix3d simpson(const Vector3d& w, double t, int power) {
    const int n = 20000;
    const double h = t / n;
    Matrix3d sum = Matrix3d::Zero();
    for (int i = 0; i <= n; ++i) {
        const double tau = i * h;
        const double weight = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += weight * std::pow(tau, power) * rodrigues(w, tau);
    }
    return sum * h / 3;
}

TEST(DisDeadReckoning, r1_and_r2_are_the_integrals_of_the_turning_body) {
    double worst = 0;
    for (const double rate : {0.0, 1e-7, 0.02, 0.0999, 0.1001, 0.7, 3.0})
        for (const double t : {0.5, 1.0, -1.0, -20.0}) {           // back in time too
            const Vector3d w = rate * Vector3d(0.48, -0.6, 0.64);  // |axis| = 1
            const Matrix3d r1 = integral_r1(w, t), r2 = integral_r2(w, t);
            worst = std::max({worst, (r1 - simpson(w, t, 0)).norm() / r1.norm(),
                              (r2 - simpson(w, t, 1)).norm() / r2.norm(),
                              (rotation_exp(w, t) - rodrigues(w, t)).norm()});
        }
    std::printf("R1, R2 and exp against Simpson / Rodrigues: worst relative %.2e\n", worst);
    EXPECT_LT(worst, 1e-11);
}

// The series and the closed form meet at |ω|·T = 0.1 without a step (either side of it by
// 1e-15 relative, where the integrals themselves move by about 1e-16).
TEST(DisDeadReckoning, the_series_and_the_closed_form_agree_at_the_switch) {
    const Vector3d axis(0, 0.6, 0.8);
    const double lo = 0.1 * (1 - 1e-15), hi = 0.1 * (1 + 1e-15);
    ASSERT_LT(lo, 0.1);
    ASSERT_GE(hi, 0.1);
    EXPECT_LT((integral_r2(axis * lo, 1.0) - integral_r2(axis * hi, 1.0)).norm(), 1e-14);
    EXPECT_LT((integral_r1(axis * lo, 1.0) - integral_r1(axis * hi, 1.0)).norm(), 1e-14);
    EXPECT_LT((rotation_exp(axis * lo, 1.0) - rotation_exp(axis * hi, 1.0)).norm(), 1e-14);
}

// Facing north, level, at latitude 0 and longitude 0: body x is ECEF z (north), y is ECEF y
// (east), z is −ECEF x (down): ψ = 0, θ = −π/2, φ = 0. Angles come back from their matrix.
TEST(DisDeadReckoning, euler_angles_turn_the_body_into_ecef) {
    const Matrix3d r = body_to_ecef(0, -std::numbers::pi / 2, 0);
    EXPECT_LT((r.col(0) - Vector3d::UnitZ()).norm(), 1e-15);
    EXPECT_LT((r.col(1) - Vector3d::UnitY()).norm(), 1e-15);
    EXPECT_LT((r.col(2) + Vector3d::UnitX()).norm(), 1e-15);
    const Vector3d e = euler_of(r);  // at θ = −π/2 ψ and φ share an axis: the matrix must return
    EXPECT_LT((body_to_ecef(e.x(), e.y(), e.z()) - r).norm(), 1e-12);
    for (const Vector3d& a : {Vector3d(0.3, -0.2, 1.1), Vector3d(-2.9, 1.2, -3.0)})
        EXPECT_LT((euler_of(body_to_ecef(a.x(), a.y(), a.z())) - a).norm(), 1e-12);
}

// World frame: P0 + V·Δt (FPW, RPW) and + ½·A·Δt² (RVW, FVW), exactly; the F ones keep the
// attitude, the R ones turn it by exp([ω]×Δt) in body axes; static stays.
TEST(DisDeadReckoning, world_algorithms_are_their_closed_forms) {
    const double dt = 2.5;
    for (std::uint8_t alg = 1; alg <= 5; ++alg) {
        const EntityState s = moving(alg);
        const Kinematics k = dead_reckon(s, dt);
        Vector3d want = s.location;
        if (alg >= 2) want += s.velocity.cast<double>() * dt;
        if (alg == 4 || alg == 5) want += 0.5 * s.dr_acceleration.cast<double>() * dt * dt;
        EXPECT_LT((k.location - want).norm(), 1e-9) << int(alg);
        const Matrix3d r0 = body_to_ecef(s.psi, s.theta, s.phi);
        const Matrix3d r = alg == 3 || alg == 4
                               ? Matrix3d(r0 * rodrigues(s.dr_angular_velocity.cast<double>(), dt))
                               : r0;
        EXPECT_LT((k.body_to_ecef - r).norm(), 1e-12) << int(alg);
    }
}

// RPB: 10 m/s forward, turning right at 0.5 rad/s: after half a turn (2π s) the entity stands
// 2·V/ω = 40 m to the right of where it started, facing back.
TEST(DisDeadReckoning, a_turning_body_flies_a_circle) {
    EntityState s;
    s.location = {1e6, 2e6, 3e6};
    s.psi = 0.7f;
    s.theta = 0.2f;
    s.phi = -0.3f;
    const Matrix3d r0 = body_to_ecef(s.psi, s.theta, s.phi);
    s.velocity = {10, 0, 0};  // body axes (algorithm 7)
    s.dr_angular_velocity = {0, 0, 0.5f};
    s.dr_algorithm = 7;
    const Kinematics k = dead_reckon(s, 2 * std::numbers::pi);
    const Vector3d moved = r0.transpose() * (k.location - s.location);
    std::printf("half a turn at 10 m/s, 0.5 rad/s: moved (%.6f, %.6f, %.6f) m in body axes\n",
                moved.x(), moved.y(), moved.z());
    EXPECT_LT((moved - Vector3d(0, 40, 0)).norm(), 1e-5);  // float velocity
    EXPECT_LT((r0.transpose() * k.body_to_ecef.col(0) + Vector3d::UnitX()).norm(), 1e-6);
}

// Body frame: the state integrated by classical Runge–Kutta (Simpson's rule: the rate depends on
// time only), dP/dt = R0·exp([ω]×t)·(Vb + Ab·t)
// (Ab only for RVB and FVB, ω only for RPB and RVB), within 1e-9 m after 3 s.
TEST(DisDeadReckoning, body_algorithms_match_an_integration_of_the_motion) {
    const double dt = 3.0;
    for (std::uint8_t alg = 6; alg <= 9; ++alg) {
        const EntityState s = moving(alg);
        const Matrix3d r0 = body_to_ecef(s.psi, s.theta, s.phi);
        const bool rotating = alg == 7 || alg == 8, accelerating = alg == 8 || alg == 9;
        const Vector3d w =
            rotating ? Vector3d(s.dr_angular_velocity.cast<double>()) : Vector3d::Zero();
        const Vector3d vb = s.velocity.cast<double>();  // body axes
        const Vector3d ab =
            accelerating ? Vector3d(s.dr_acceleration.cast<double>()) : Vector3d::Zero();
        const auto f = [&](double t) { return Vector3d(r0 * rodrigues(w, t) * (vb + ab * t)); };
        Vector3d p = Vector3d::Zero();  // the displacement (summed onto 6.4e6 m it would round)
        const int steps = 3000;
        const double h = dt / steps;
        for (int i = 0; i < steps; ++i) {
            const double t = i * h;
            p += h / 6 * (f(t) + 4 * f(t + h / 2) + f(t + h));
        }
        const Kinematics k = dead_reckon(s, dt);
        EXPECT_LT((k.location - s.location - p).norm(), 1e-9) << int(alg);
        const Matrix3d r = rotating ? Matrix3d(r0 * rodrigues(w, dt)) : r0;
        EXPECT_LT((k.body_to_ecef - r).norm(), 1e-12) << int(alg);
    }
}

}  // namespace
}  // namespace mirage::dis
