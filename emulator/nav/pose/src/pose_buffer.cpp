// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/pose_buffer.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::navpose {
namespace {

constexpr int kJumpsBeforeReset = 10;  // a persistent offset is a re-initialisation, not a glitch

double seconds(core::Nanos d) { return double(d.count()) * 1e-9; }

}  // namespace

PoseBuffer::PoseBuffer(PoseBufferConfig config) : cfg_(config) {}

Eigen::Vector3d PoseBuffer::velocity_at_end() const {
    if (pos_.empty()) return Eigen::Vector3d::Zero();
    const PosSample& b = pos_.back();
    if (b.v) return *b.v;
    if (pos_.size() < 2) return Eigen::Vector3d::Zero();
    const PosSample& a = pos_[pos_.size() - 2];
    return (b.p - a.p) / seconds(b.t - a.t);
}

AddStatus PoseBuffer::add_position(core::GpsTime t, const Eigen::Vector3d& local,
                                   const std::optional<Eigen::Vector3d>& velocity) {
    std::lock_guard lk(mu_);
    if (!local.allFinite() || (velocity && !velocity->allFinite())) {
        ++counters_.not_finite;
        return AddStatus::NotFinite;
    }
    if (!pos_.empty()) {
        const PosSample& b = pos_.back();
        if (t == b.t) {
            ++counters_.duplicates;
            return AddStatus::Duplicate;
        }
        if (t < b.t) {
            ++counters_.time_backwards;
            return AddStatus::TimeBackwards;
        }
        if (t - b.t > cfg_.history) {
            pos_.clear();  // after a long silence the track starts afresh
        } else {
            const Eigen::Vector3d predicted = b.p + velocity_at_end() * seconds(t - b.t);
            if ((local - predicted).norm() > cfg_.max_jump_m) {
                ++counters_.position_jumps;
                if (++consecutive_jumps_ < kJumpsBeforeReset) return AddStatus::PositionJump;
                pos_.clear();
            }
        }
    }
    consecutive_jumps_ = 0;
    pos_.push_back({t, local, velocity});
    while (pos_.size() > 2 && pos_.back().t - pos_.front().t > cfg_.history) pos_.pop_front();
    ++counters_.accepted;
    return AddStatus::Accepted;
}

AddStatus PoseBuffer::add_attitude(core::GpsTime t, const Eigen::Quaterniond& attitude) {
    std::lock_guard lk(mu_);
    const double n = attitude.norm();
    if (!attitude.coeffs().allFinite() || !(n > 0.5 && n < 2.0)) {
        ++counters_.not_finite;
        return AddStatus::NotFinite;
    }
    if (!att_.empty() && t == att_.back().t) {
        ++counters_.duplicates;
        return AddStatus::Duplicate;
    }
    if (!att_.empty() && t < att_.back().t) {
        ++counters_.time_backwards;
        return AddStatus::TimeBackwards;
    }
    if (!att_.empty() && t - att_.back().t > cfg_.history) att_.clear();
    att_.push_back({t, attitude.normalized()});
    while (att_.size() > 2 && att_.back().t - att_.front().t > cfg_.history) att_.pop_front();
    ++counters_.accepted;
    return AddStatus::Accepted;
}

PoseBuffer::Query PoseBuffer::at_locked(core::GpsTime t) const {
    Query q;
    if (pos_.empty() || att_.empty()) return q;
    const core::GpsTime newest = std::min(pos_.back().t, att_.back().t);
    q.age = t - newest;
    if (t < pos_.front().t || t < att_.front().t || q.age > cfg_.max_extrapolation) {
        q.status = PoseStatus::Stale;
        return q;
    }
    q.status = q.age > core::Nanos(0) ? PoseStatus::Extrapolated : PoseStatus::Interpolated;

    // Position: linear between the bracketing samples, constant velocity beyond the newest.
    if (t >= pos_.back().t) {
        q.pose.position = pos_.back().p + velocity_at_end() * seconds(t - pos_.back().t);
    } else {
        const auto it = std::upper_bound(pos_.begin(), pos_.end(), t,
                                         [](core::GpsTime x, const PosSample& s) { return x < s.t; });
        const PosSample& b = *it;
        const PosSample& a = *(it - 1);
        const double f = double((t - a.t).count()) / double((b.t - a.t).count());
        q.pose.position = a.p + f * (b.p - a.p);
    }
    // Attitude: slerp between samples; beyond the newest, the last angular rate continues.
    if (t >= att_.back().t) {
        const AttSample& b = att_.back();
        q.pose.attitude = b.q;
        if (att_.size() >= 2 && t > b.t) {
            const AttSample& a = att_[att_.size() - 2];
            Eigen::AngleAxisd step(a.q.conjugate() * b.q);
            step.angle() *= double((t - b.t).count()) / double((b.t - a.t).count());
            q.pose.attitude = (b.q * Eigen::Quaterniond(step)).normalized();
        }
    } else {
        const auto it = std::upper_bound(att_.begin(), att_.end(), t,
                                         [](core::GpsTime x, const AttSample& s) { return x < s.t; });
        const AttSample& b = *it;
        const AttSample& a = *(it - 1);
        const double f = double((t - a.t).count()) / double((b.t - a.t).count());
        q.pose.attitude = a.q.slerp(f, b.q).normalized();
    }
    return q;
}

PoseBuffer::Query PoseBuffer::at(core::GpsTime t) const {
    std::lock_guard lk(mu_);
    return at_locked(t);
}

std::optional<core::Trajectory> PoseBuffer::window(core::GpsTime t0, core::GpsTime t1,
                                                   core::Nanos step) const {
    std::lock_guard lk(mu_);
    std::vector<core::StampedPose> samples;
    if (step <= core::Nanos(0)) step = t1 - t0;
    for (core::GpsTime t = t0;; t += step) {
        if (t > t1) t = t1;
        const Query q = at_locked(t);
        if (q.status == PoseStatus::Stale || q.status == PoseStatus::Empty) return std::nullopt;
        samples.push_back({t, q.pose});
        if (t == t1) break;
    }
    return core::Trajectory(std::move(samples));
}

std::optional<core::GpsTime> PoseBuffer::newest() const {
    std::lock_guard lk(mu_);
    if (pos_.empty() || att_.empty()) return std::nullopt;
    return std::min(pos_.back().t, att_.back().t);
}

PoseBufferCounters PoseBuffer::counters() const {
    std::lock_guard lk(mu_);
    return counters_;
}

}  // namespace mirage::navpose
