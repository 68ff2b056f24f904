// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/track_gate.hpp"

#include "seconds.hpp"

namespace mirage::navpose {
namespace {

constexpr int kJumpsBeforeReset = 10;  // a persistent offset is a re-initialisation, not a glitch

}  // namespace

TrackGate::TrackGate(TrackGateConfig config) : cfg_(config) {}

// Constant velocity from the newest fix: its reported velocity, else the last two fixes'.
Eigen::Vector3d TrackGate::predicted(core::GpsTime t) const {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    if (last_->v)
        v = *last_->v;
    else if (before_last_)
        v = (last_->p - before_last_->p) / detail::seconds(last_->t - before_last_->t);
    return last_->p + v * detail::seconds(t - last_->t);
}

GateVerdict TrackGate::position(core::GpsTime t, const Eigen::Vector3d& local,
                                const std::optional<Eigen::Vector3d>& velocity) {
    if (!local.allFinite() || (velocity && !velocity->allFinite()))
        return {AddStatus::NotFinite, false};
    GateVerdict verdict{AddStatus::Accepted, !last_};
    if (last_) {
        if (t == last_->t) return {AddStatus::Duplicate, false};
        if (t < last_->t) return {AddStatus::TimeBackwards, false};
        if (t - last_->t > cfg_.restart_after) {
            verdict.restart = true;
        } else if ((local - predicted(t)).norm() > cfg_.max_jump_m) {
            if (++consecutive_jumps_ < kJumpsBeforeReset) return {AddStatus::PositionJump, false};
            verdict = {AddStatus::Reinitialised, true};
        }
    }
    consecutive_jumps_ = 0;
    before_last_ = verdict.restart ? std::nullopt : last_;
    last_ = Fix{t, local, velocity};
    return verdict;
}

GateVerdict TrackGate::attitude(core::GpsTime t, const Eigen::Quaterniond& attitude) {
    const double n = attitude.norm();
    if (!attitude.coeffs().allFinite() || !(n > 0.5 && n < 2.0))
        return {AddStatus::NotFinite, false};
    GateVerdict verdict{AddStatus::Accepted, !last_attitude_};
    if (last_attitude_) {
        if (t == *last_attitude_) return {AddStatus::Duplicate, false};
        if (t < *last_attitude_) return {AddStatus::TimeBackwards, false};
        verdict.restart = t - *last_attitude_ > cfg_.restart_after;
    }
    last_attitude_ = t;
    return verdict;
}

}  // namespace mirage::navpose
