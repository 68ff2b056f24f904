// SPDX-License-Identifier: Apache-2.0
// DIS dead reckoning (IEEE 1278.1 Annex E; docs/dis.md §2): an Entity State PDU's pose
// extrapolated Δt seconds past its timestamp by its algorithm, 1 static to 9 FVB.
#pragma once
#include <Eigen/Core>

#include "mirage/dis/entity_state.hpp"

namespace mirage::dis {

// Body-to-ECEF rotation of DIS Euler angles: Rz(ψ)·Ry(θ)·Rx(φ) (body x forward, y right, z
// down), and back (θ in [−π/2, π/2], ψ and φ in (−π, π]).
Eigen::Matrix3d body_to_ecef(double psi, double theta, double phi);
Eigen::Vector3d euler_of(const Eigen::Matrix3d& body_to_ecef);

// ∫₀ᵀ exp([ω]×·τ) dτ (R1) and ∫₀ᵀ exp([ω]×·τ)·τ dτ (R2) in closed form, by series below
// |ω|·|T| = 0.1 where the closed form cancels; T may be negative.
Eigen::Matrix3d integral_r1(const Eigen::Vector3d& omega, double t);
Eigen::Matrix3d integral_r2(const Eigen::Vector3d& omega, double t);
// exp([ω]×·T) (Rodrigues).
Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& omega, double t);

struct Kinematics {
    Eigen::Vector3d location{Eigen::Vector3d::Zero()};  // ECEF, m
    Eigen::Vector3d velocity{Eigen::Vector3d::Zero()};  // ECEF axes, m/s (the position's rate)
    Eigen::Matrix3d body_to_ecef{Eigen::Matrix3d::Identity()};
};

// The PDU's pose `dt` seconds on. Algorithms: 0 (other) and 1 static; world frame 2 FPW,
// 3 RPW, 4 RVW, 5 FVW: P0 + V·Δt (+ ½·A·Δt² for the V ones); body frame 6 FPB, 7 RPB, 8 RVB,
// 9 FVB: P0 + R0·(R1·Vb + R2·Ab), Vb and Ab the PDU's velocity and acceleration in body axes. The R
// (rotating) ones turn the attitude as R0·exp([ω]×·Δt), ω in body axes; the F ones keep it.
// The velocity is the position's rate: V (+ A·Δt), or R0·exp([ω]×Δt)·(Vb + Ab·Δt) in body frame.
Kinematics dead_reckon(const EntityState& s, double dt);

}  // namespace mirage::dis
