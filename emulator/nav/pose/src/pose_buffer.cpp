// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/pose_buffer.hpp"

#include <algorithm>
#include <cmath>

#include "seconds.hpp"

namespace mirage::navpose {
namespace {

// The rotation `r` continued by the factor f (shortest way round). Written out rather than
// through Eigen::AngleAxisd, whose stableNorm trips g++ 12's maybe-uninitialized on AVX-512.
Eigen::Quaterniond scaled_rotation(Eigen::Quaterniond r, double f) {
    if (r.w() < 0) r.coeffs() = -r.coeffs();
    const double s = r.vec().norm();
    if (!(s > 0)) return Eigen::Quaterniond::Identity();
    return Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * std::atan2(s, r.w()) * f, r.vec() / s));
}

void note(std::vector<UsedMessage>* used, const MessageTag& tag, Track track) {
    if (!used) return;
    const UsedMessage m{tag, track};
    if (std::find(used->begin(), used->end(), m) == used->end()) used->push_back(m);
}

// Index of the first sample after t.
template <class Deque>
std::size_t upper_index(const Deque& d, core::GpsTime t) {
    const auto it = std::upper_bound(d.begin(), d.end(), t,
                                     [](core::GpsTime x, const auto& s) { return x < s.t; });
    return static_cast<std::size_t>(it - d.begin());
}

}  // namespace

PoseBuffer::PoseBuffer(PoseBufferConfig config) : cfg_(config) {}

Eigen::Vector3d PoseBuffer::velocity_at_end() const {
    if (pos_.empty()) return Eigen::Vector3d::Zero();
    const PosSample& b = pos_.back();
    if (b.v) return *b.v;
    if (pos_.size() < 2) return Eigen::Vector3d::Zero();
    const PosSample& a = pos_[pos_.size() - 2];
    return (b.p - a.p) / detail::seconds(b.t - a.t);
}

void PoseBuffer::add(const PositionUpdate& u) {
    std::lock_guard lk(mu_);
    if (u.restart) pos_.clear();
    if (!pos_.empty() && u.t <= pos_.back().t) return;
    pos_.push_back({u.t, u.local, u.velocity, u.tag});
    while (pos_.size() > 2 && pos_.back().t - pos_.front().t > cfg_.history) pos_.pop_front();
}

void PoseBuffer::add(const AttitudeUpdate& u) {
    std::lock_guard lk(mu_);
    if (u.restart) att_.clear();
    if (!att_.empty() && u.t <= att_.back().t) return;
    att_.push_back({u.t, u.attitude.normalized(), u.tag});
    while (att_.size() > 2 && att_.back().t - att_.front().t > cfg_.history) att_.pop_front();
}

PoseBuffer::Query PoseBuffer::at_locked(core::GpsTime t, std::vector<UsedMessage>* used) const {
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
        q.pose.position = pos_.back().p + velocity_at_end() * detail::seconds(t - pos_.back().t);
        note(used, pos_.back().tag, Track::Position);
    } else {
        const std::size_t i = upper_index(pos_, t);
        const PosSample& a = pos_[i - 1];
        const PosSample& b = pos_[i];
        const double f = double((t - a.t).count()) / double((b.t - a.t).count());
        q.pose.position = a.p + f * (b.p - a.p);
        note(used, a.tag, Track::Position);
        if (f > 0) note(used, b.tag, Track::Position);
    }
    // Attitude: slerp between samples; beyond the newest, the last angular rate continues.
    if (t >= att_.back().t) {
        const AttSample& b = att_.back();
        q.pose.attitude = b.q;
        if (att_.size() >= 2 && t > b.t) {
            const AttSample& a = att_[att_.size() - 2];
            const double f = double((t - b.t).count()) / double((b.t - a.t).count());
            q.pose.attitude = (b.q * scaled_rotation(a.q.conjugate() * b.q, f)).normalized();
        }
        note(used, b.tag, Track::Attitude);
    } else {
        const std::size_t i = upper_index(att_, t);
        const AttSample& a = att_[i - 1];
        const AttSample& b = att_[i];
        const double f = double((t - a.t).count()) / double((b.t - a.t).count());
        q.pose.attitude = a.q.slerp(f, b.q).normalized();
        note(used, a.tag, Track::Attitude);
        if (f > 0) note(used, b.tag, Track::Attitude);
    }
    return q;
}

PoseBuffer::Query PoseBuffer::at(core::GpsTime t) const {
    std::lock_guard lk(mu_);
    return at_locked(t, nullptr);
}

std::optional<PoseWindow> PoseBuffer::window(core::GpsTime t0, core::GpsTime t1,
                                             core::Nanos step) const {
    std::lock_guard lk(mu_);
    std::vector<core::StampedPose> samples;
    std::vector<UsedMessage> used;
    if (step <= core::Nanos(0)) step = t1 - t0;
    for (core::GpsTime t = t0;; t += step) {
        if (t > t1) t = t1;
        const Query q = at_locked(t, &used);
        if (q.status == PoseStatus::Stale || q.status == PoseStatus::Empty) return std::nullopt;
        samples.push_back({t, q.pose});
        if (t == t1) break;
    }
    return PoseWindow{core::Trajectory(std::move(samples)), std::move(used)};
}

std::optional<core::GpsTime> PoseBuffer::newest() const {
    std::lock_guard lk(mu_);
    if (pos_.empty() || att_.empty()) return std::nullopt;
    return std::min(pos_.back().t, att_.back().t);
}

}  // namespace mirage::navpose
