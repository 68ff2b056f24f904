// SPDX-License-Identifier: Apache-2.0
#include "ray_batch.hpp"

#include <cmath>

#include "basis.hpp"
#include "mirage/render/trace_batches.hpp"

namespace mirage::render {
namespace {

// Exact poses are computed about this often in firing time (see blend_batch_poses).
constexpr core::Nanos kPoseSpacing{200'000};

// Pulses between exact poses: kPoseSpacing at the sensor's mean rate, 1 to 256 (1 for a rate that
// is not a positive number).
std::size_t pose_stride(double pulse_rate_hz) {
    const double pulses = pulse_rate_hz * 1e-9 * static_cast<double>(kPoseSpacing.count());
    return pulses >= 2.0 ? static_cast<std::size_t>(std::min(256.0, pulses)) : 1;
}

// Pulses [i, end) of a batch between two exact poses: origin o0 + f·dor, direction
// (m0 + f·dm)·v normalised, f the fraction of the interval from t0 to t1. One loop over arrays
// without branches, so it vectorises (the matrices are passed as values: the compiler cannot tell
// them from the outputs otherwise).
void blend_poses(const double* __restrict t, const double* __restrict vx,
                 const double* __restrict vy, const double* __restrict vz, std::size_t i,
                 std::size_t end, double t0, double t1, const std::array<double, 9> m0,
                 const std::array<double, 9> dm, const std::array<double, 3> o0,
                 const std::array<double, 3> dor, double* __restrict ox, double* __restrict oy,
                 double* __restrict oz, double* __restrict dx, double* __restrict dy,
                 double* __restrict dz) {
    const double inv_dt = t1 != t0 ? 1.0 / (t1 - t0) : 0.0;
    for (std::size_t k = i; k < end; ++k) {
        const double f = (t[k] - t0) * inv_dt;
        const double x =
            (m0[0] + f * dm[0]) * vx[k] + (m0[1] + f * dm[1]) * vy[k] + (m0[2] + f * dm[2]) * vz[k];
        const double y =
            (m0[3] + f * dm[3]) * vx[k] + (m0[4] + f * dm[4]) * vy[k] + (m0[5] + f * dm[5]) * vz[k];
        const double z =
            (m0[6] + f * dm[6]) * vx[k] + (m0[7] + f * dm[7]) * vy[k] + (m0[8] + f * dm[8]) * vz[k];
        const double inv = 1.0 / std::sqrt(x * x + y * y + z * z);
        ox[k] = o0[0] + f * dor[0];
        oy[k] = o0[1] + f * dor[1];
        oz[k] = o0[2] + f * dor[2];
        dx[k] = x * inv;
        dy[k] = y * inv;
        dz[k] = z * inv;
    }
}

// Row-major entries of a 3×3 matrix.
std::array<double, 9> entries(const Eigen::Matrix3d& m) {
    return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

}  // namespace

std::size_t trace_batch_pulses(const sensor::SensorModel& sensor) {
    return chunk_pulses(sensor, kTraceBatchPulses);
}

RayBatchBuilder::RayBatchBuilder(const sensor::SensorModel& sensor,
                                 const core::Trajectory& trajectory, const core::Mount& mount,
                                 core::GpsTime start)
    : sensor_(sensor),
      trajectory_(trajectory),
      mount_(mount.as_pose()),
      start_(start),
      subrays_(sensor::footprint(sensor.beam.sub_rays, sensor.beam.profile,
                                 sensor.beam.divergence_rad, sensor.beam.footprint_radius)),
      group_(std::max<std::uint32_t>(1, sensor.scan->group_size())),
      pose_stride_(pose_stride(sensor.scan->pulse_rate_hz())),
      batch_(trace_batch_pulses(sensor)) {
    // d + a·u + b·v has length √(1 + a² + b²) for orthonormal (d, u, v): normalise with a
    // precomputed factor instead of a square root per sub-ray.
    for (const auto& s : subrays_) {
        const double a = std::tan(double(s.dx)), b = std::tan(double(s.dy));
        tanf_.push_back({static_cast<float>(a), static_cast<float>(b)});
        inv_normf_.push_back(static_cast<float>(1.0 / std::sqrt(1.0 + a * a + b * b)));
    }
    if (sensor.beam.adaptive_footprint) probes_ = footprint_probes(subrays_.size());
}

void RayBatchBuilder::build(std::uint64_t first, std::size_t n, RayBatch& g) const {
    build_lines(first, n, g);
    if (n > 0) make_rays(g);
}

void RayBatchBuilder::build_lines(std::uint64_t first, std::size_t n, RayBatch& g) const {
    g.builder = this;
    load_pulses(first, n, g);
    g.rays.clear();
    g.first_ray.clear();
    if (n > 0) blend_batch_poses(g);
}

// The batch's pulse specs, and the pose loop's inputs copied out of them.
void RayBatchBuilder::load_pulses(std::uint64_t first, std::size_t n, RayBatch& g) const {
    g.first = first;
    g.specs.resize(n);
    sensor_.scan->pulses(first, n, g.specs.data());
    for (int a = 0; a < 3; ++a) {
        g.origin[a].resize(n);
        g.direction[a].resize(n);
        g.v[a].resize(n);
    }
    g.t.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        g.t[i] = double(g.specs[i].t_ns);
        for (int a = 0; a < 3; ++a) g.v[a][i] = double(g.specs[i].dir[a]);
    }
}

// Exact poses (slerp on the trajectory) at the knots, the pulses whose index is a multiple of
// pose_stride_ (~kPoseSpacing apart); pulses between blend the two bracketing poses (positions
// linearly, rotation matrices linearly with the direction renormalised), which removes the
// trigonometry from the per-pulse cost. Over 200 µs an attitude turning at 90°/s moves
// θ = 3.1e-4 rad, and the blend differs from slerp by at most θ²/16 = 6e-9 rad (12 µm at 2 km;
// checked numerically over random axes); positions differ from the cubic by a·h²/8 = 5e-8 m at
// 10 m/s². Knots by global index make a pulse's pose independent of how pulses are batched. The
// pose at the end of one interval starts the next: one trajectory lookup (~200 cycles) per knot.
void RayBatchBuilder::blend_batch_poses(RayBatch& g) const {
    const std::uint64_t first = g.first, last = first + g.specs.size();
    std::size_t hint = 0;
    sensor::PulseSpec outside;
    const auto time_of = [&](std::uint64_t k) {  // a knot's firing time, ns
        if (k >= first && k < last) return g.specs[k - first].t_ns;
        sensor_.scan->pulses(k, 1, &outside);
        return outside.t_ns;
    };
    const auto pose_at = [&](std::int64_t t) {
        return trajectory_.at(start_ + core::Nanos(t), hint) * mount_;
    };
    std::uint64_t k = first / pose_stride_ * pose_stride_;
    std::int64_t t1 = time_of(k);
    core::Pose p1 = pose_at(t1);
    Eigen::Matrix3d m1 = p1.attitude.toRotationMatrix();
    for (; k < last; k += pose_stride_) {
        const std::int64_t t0 = t1;
        const core::Pose p0 = p1;
        const Eigen::Matrix3d m0 = m1;
        t1 = time_of(k + pose_stride_);
        p1 = pose_at(t1);
        m1 = p1.attitude.toRotationMatrix();
        const Eigen::Vector3d dor = p1.position - p0.position;
        blend_poses(
            g.t.data(), g.v[0].data(), g.v[1].data(), g.v[2].data(), std::max(k, first) - first,
            std::min(k + pose_stride_, last) - first, double(t0), double(t1), entries(m0),
            entries(m1 - m0), {p0.position.x(), p0.position.y(), p0.position.z()},
            {dor.x(), dor.y(), dor.z()}, g.origin[0].data(), g.origin[1].data(), g.origin[2].data(),
            g.direction[0].data(), g.direction[1].data(), g.direction[2].data());
    }
}

// Ray order: one channel over neighbouring groups, sub-rays adjacent: packets of one beam over
// neighbouring azimuths stay coherent, which firing order does not (docs/physics.md §4.3).
void RayBatchBuilder::make_rays(RayBatch& g) const {
    const std::size_t n = g.specs.size();
    const std::size_t s_count = subrays_.size();
    g.rays.resize(n * s_count);
    g.first_ray.resize(n);
    const std::size_t groups = (n + group_ - 1) / group_;
    const auto tfar = static_cast<float>(sensor_.receiver.max_range_m);
    std::size_t r = 0;
    for (std::size_t c = 0; c < group_; ++c) {
        for (std::size_t gi = 0; gi < groups; ++gi) {
            const std::size_t i = gi * group_ + c;
            if (i >= n) continue;
            const Eigen::Vector3d d = g.direction_of(i);
            g.first_ray[i] = static_cast<std::uint32_t>(r);
            Ray base;
            base.ox = static_cast<float>(g.origin[0][i]);
            base.oy = static_cast<float>(g.origin[1][i]);
            base.oz = static_cast<float>(g.origin[2][i]);
            base.dx = static_cast<float>(d.x());
            base.dy = static_cast<float>(d.y());
            base.dz = static_cast<float>(d.z());
            base.tnear = 0.0f;
            base.tfar = tfar;
            g.rays[r++] = base;
            if (s_count == 1) continue;
            add_subrays(base, d, &g.rays[r], probes_.empty() ? Part::All : Part::Probes);
            r += s_count - 1;
        }
    }
}

// Sub-rays 1.. of a pulse whose central ray is `base` along unit d, into out[0, S - 1). In float:
// rays are float anyway, and the offsets are milliradians, far above float's 6e-8 relative
// resolution.
void RayBatchBuilder::add_subrays(const Ray& base, const Eigen::Vector3d& d, Ray* out, Part part,
                                  float spread) const {
    Eigen::Vector3d u, v;
    orthonormal_basis(d, u, v);
    const Eigen::Vector3f df = d.cast<float>(), uf = spread * u.cast<float>(),
                          vf = spread * v.cast<float>();
    for (std::size_t s = 1; s < subrays_.size(); ++s) {
        if (part != Part::All && (probes_[s] != 0) != (part == Part::Probes)) continue;
        const Eigen::Vector3f dt = df + tanf_[s].first * uf + tanf_[s].second * vf;
        const Eigen::Vector3f ds = spread == 1.0f ? dt * inv_normf_[s] : dt.normalized();
        Ray ray = base;
        ray.dx = ds.x();
        ray.dy = ds.y();
        ray.dz = ds.z();
        out[s - 1] = ray;
    }
}

// Around the central ray as traced (a wandering beam's turned one), in the probes' place kept.
void RayBatchBuilder::complete(RayBatch& g, std::size_t r, double spread) const {
    const Ray& c = g.rays[r];
    add_subrays(c, Eigen::Vector3d(c.dx, c.dy, c.dz).normalized(), &g.rays[r + 1], Part::Rest,
                static_cast<float>(spread));
}

std::vector<std::uint8_t> footprint_probes(std::size_t subrays) {
    std::vector<std::uint8_t> mask(subrays, 0);
    if (subrays == 0) return mask;
    mask[0] = 1;
    const int rings = sensor::ring_count(static_cast<int>(subrays));
    if (rings <= 0) return mask;
    const auto k = static_cast<std::size_t>(rings);
    const std::size_t outer = 1 + 3 * k * (k - 1);
    for (std::size_t p = 0; p < 6; ++p) mask[outer + p * k] = 1;
    return mask;
}

struct TraceBatches::Impl {
    explicit Impl(const Setup& s) : builder(s.sensor, s.trajectory, s.mount, s.options.start) {}
    RayBatchBuilder builder;
    RayBatch g;
};

TraceBatches::TraceBatches(const Setup& setup) : impl_(std::make_unique<Impl>(setup)) {}

TraceBatches::~TraceBatches() = default;

void TraceBatches::for_each(std::uint64_t first, std::size_t n,
                            const std::function<void(std::span<const Ray>)>& fn) {
    impl_->builder.for_each_batch(first, n, impl_->g, [&](const RayBatch& b) { fn(b.rays); });
}

}  // namespace mirage::render
