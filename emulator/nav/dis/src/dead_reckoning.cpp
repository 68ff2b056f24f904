// SPDX-License-Identifier: Apache-2.0
// DIS dead reckoning (docs/dis.md §2).
#include "mirage/dis/dead_reckoning.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "mirage/core/pose.hpp"

namespace mirage::dis {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
    Eigen::Matrix3d m;
    m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    return m;
}

// The coefficients of I, Ω and Ω² (Ω = [ω]×, x = |ω|·T): sin x/|ω|, (1 − cos x)/|ω|²,
// (x − sin x)/|ω|³, (sin x − x·cos x)/|ω|³ and (T²/2 − (cos x + x·sin x − 1)/|ω|²)/|ω|².
// Below |x| = 0.1 by their series to x⁶ (the next terms are under 3e-14 of the first), since
// the closed forms lose digits to cancellation there (the last one most, as 1/x⁴).
struct Coefficients {
    double s, a, b, c, e;
};

Coefficients coefficients(double w, double t) {
    const double x = w * t, x2 = x * x;
    if (std::abs(x) < 0.1) {  // (Δt may be negative: a PDU newer than the time asked)
        const double t2 = t * t, t3 = t2 * t;
        return {t * (1 - x2 / 6 * (1 - x2 / 20 * (1 - x2 / 42))),
                t2 * (0.5 - x2 / 24 + x2 * x2 / 720 - x2 * x2 * x2 / 40320),
                t3 * (1.0 / 6 - x2 / 120 + x2 * x2 / 5040 - x2 * x2 * x2 / 362880),
                t3 * (1.0 / 3 - x2 / 30 + x2 * x2 / 840 - x2 * x2 * x2 / 45360),
                t2 * t2 * (1.0 / 8 - x2 / 144 + 7 * x2 * x2 / 40320 - 9 * x2 * x2 * x2 / 3628800)};
    }
    const double sx = std::sin(x), cx = std::cos(x), w2 = w * w, w3 = w2 * w;
    return {sx / w, (1 - cx) / w2, (x - sx) / w3, (sx - x * cx) / w3,
            (t * t / 2 - (cx + x * sx - 1) / w2) / w2};
}

}  // namespace

// DIS's ψ, θ, φ are Mirage's yaw, pitch and roll about ECEF axes (core/pose.hpp), whose inverse
// also holds at θ = ±π/2, where a platform level at the equator or the poles sits.
Eigen::Matrix3d body_to_ecef(double psi, double theta, double phi) {
    return core::quaternion_from_rpy(phi, theta, psi).toRotationMatrix();
}

Eigen::Vector3d euler_of(const Eigen::Matrix3d& r) {
    const Eigen::Vector3d rpy = core::rpy_from_quaternion(Eigen::Quaterniond(r));
    return {rpy.z(), rpy.y(), rpy.x()};
}

Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& omega, double t) {
    const Coefficients k = coefficients(omega.norm(), t);
    const Eigen::Matrix3d o = skew(omega);
    return Eigen::Matrix3d::Identity() + k.s * o + k.a * o * o;
}

Eigen::Matrix3d integral_r1(const Eigen::Vector3d& omega, double t) {
    const Coefficients k = coefficients(omega.norm(), t);
    const Eigen::Matrix3d o = skew(omega);
    return t * Eigen::Matrix3d::Identity() + k.a * o + k.b * o * o;
}

Eigen::Matrix3d integral_r2(const Eigen::Vector3d& omega, double t) {
    const Coefficients k = coefficients(omega.norm(), t);
    const Eigen::Matrix3d o = skew(omega);
    return 0.5 * t * t * Eigen::Matrix3d::Identity() + k.c * o + k.e * o * o;
}

Kinematics dead_reckon(const EntityState& s, double dt) {
    Kinematics k;
    const Eigen::Matrix3d r0 = body_to_ecef(s.psi, s.theta, s.phi);
    k.location = s.location;
    k.body_to_ecef = r0;
    k.velocity = s.velocity.cast<double>();
    const int alg = s.dr_algorithm;
    if (alg <= 1 || alg > 9) {  // other, static
        k.velocity.setZero();
        return k;
    }
    const Eigen::Vector3d v = s.velocity.cast<double>();
    const Eigen::Vector3d acc = s.dr_acceleration.cast<double>();
    const Eigen::Vector3d w = s.dr_angular_velocity.cast<double>();
    const bool rotating = alg == 3 || alg == 4 || alg == 7 || alg == 8;
    const bool accelerating = alg == 4 || alg == 5 || alg == 8 || alg == 9;
    if (alg <= 5) {  // world frame
        k.location += v * dt;
        if (accelerating) {
            k.location += 0.5 * acc * dt * dt;
            k.velocity += acc * dt;
        }
    } else {  // body frame: the body-axes velocity and acceleration turn with the body
        const Eigen::Vector3d wb = rotating ? w : Eigen::Vector3d::Zero();
        const Eigen::Vector3d& vb = v;  // body axes for 6-9 (docs/dis.md §1)
        Eigen::Vector3d d = integral_r1(wb, dt) * vb;
        if (accelerating) d += integral_r2(wb, dt) * acc;
        k.location += r0 * d;
        k.velocity =
            r0 * rotation_exp(wb, dt) * (accelerating ? Eigen::Vector3d(vb + acc * dt) : vb);
    }
    if (rotating) k.body_to_ecef = r0 * rotation_exp(w, dt);
    return k;
}

}  // namespace mirage::dis
