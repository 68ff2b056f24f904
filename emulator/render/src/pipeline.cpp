// SPDX-License-Identifier: Apache-2.0
#include "mirage/render/pipeline.hpp"

#include <pthread.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <limits>
#include <mutex>
#include <numbers>
#include <span>
#include <thread>

#include "mirage/core/exp_poly.hpp"
#include "mirage/core/rng.hpp"

namespace mirage::render {
namespace {

using core::GpsTime;
using core::PointRecord;

// Exact poses are computed about this often in firing time (see ChunkBuilder::build).
constexpr core::Nanos kPoseSpacing{200'000};

// Pulses between exact poses: kPoseSpacing at the sensor's mean rate, 1 to 256 (1 for a rate that
// is not a positive number).
std::size_t pose_stride(double pulse_rate_hz) {
    const double pulses = pulse_rate_hz * 1e-9 * static_cast<double>(kPoseSpacing.count());
    return pulses >= 2.0 ? static_cast<std::size_t>(std::min(256.0, pulses)) : 1;
}

// Two unit vectors orthogonal to unit d (and to each other), for sub-ray offsets and jitter.
// Written out so each costs one square root and one division (Eigen's normalized() divides
// per component, and these divisions dominated the per-pulse profile).
inline void orthonormal_basis(const Eigen::Vector3d& d, Eigen::Vector3d& u, Eigen::Vector3d& v) {
    if (std::abs(d.z()) < 0.9) {  // u = d × z / |d × z|
        const double inv = 1.0 / std::sqrt(d.x() * d.x() + d.y() * d.y());
        u = {d.y() * inv, -d.x() * inv, 0.0};
    } else {  // u = d × x / |d × x|
        const double inv = 1.0 / std::sqrt(d.y() * d.y() + d.z() * d.z());
        u = {0.0, d.z() * inv, -d.y() * inv};
    }
    v = d.cross(u);
}

// Pulses of a chunk in firing order, their sensor poses, and the rays traced for them.
struct ChunkGeometry {
    std::vector<sensor::PulseSpec> specs;
    // Per pulse, one array per axis (so the pose loop vectorises), local frame, double: the
    // sensor origin and the nominal beam direction.
    std::array<std::vector<double>, 3> origin, direction;
    std::vector<Ray> rays;                 // tracing order
    std::vector<std::uint32_t> first_ray;  // index in `rays` of pulse i's first sub-ray; the
                                           // S sub-rays of a pulse are adjacent in `rays`
    // The pose loop's inputs, copied out of `specs`: firing time (ns from the start, exact in
    // double) and the sensor-frame direction.
    std::vector<double> t;
    std::array<std::vector<double>, 3> v;

    Eigen::Vector3d origin_of(std::size_t i) const {
        return {origin[0][i], origin[1][i], origin[2][i]};
    }
    Eigen::Vector3d direction_of(std::size_t i) const {
        return {direction[0][i], direction[1][i], direction[2][i]};
    }
};

// Pulses [i, end) of a chunk between two exact poses: origin o0 + f·dor, direction
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

class ChunkBuilder {
  public:
    ChunkBuilder(const sensor::SensorModel& sensor, const core::Trajectory& trajectory,
                 const core::Mount& mount, GpsTime start)
        : sensor_(sensor),
          trajectory_(trajectory),
          mount_(mount.as_pose()),
          start_(start),
          subrays_(sensor::footprint(sensor.beam.sub_rays, sensor.beam.profile,
                                     sensor.beam.divergence_rad)),
          group_(std::max<std::uint32_t>(1, sensor.scan->group_size())),
          pose_stride_(pose_stride(sensor.scan->pulse_rate_hz())) {
        // d + a·u + b·v has length √(1 + a² + b²) for orthonormal (d, u, v): normalise with a
        // precomputed factor instead of a square root per sub-ray.
        for (const auto& s : subrays_) {
            const double a = std::tan(double(s.dx)), b = std::tan(double(s.dy));
            tanf_.push_back({static_cast<float>(a), static_cast<float>(b)});
            inv_normf_.push_back(static_cast<float>(1.0 / std::sqrt(1.0 + a * a + b * b)));
        }
    }

    std::size_t subray_count() const { return subrays_.size(); }
    const std::vector<sensor::SubRay>& subrays() const { return subrays_; }

    void build(std::uint64_t first, std::size_t n, ChunkGeometry& g) const {
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
        // Exact poses (slerp on the trajectory) at the knots, the pulses whose index is a
        // multiple of pose_stride_ (~kPoseSpacing apart); pulses between blend the two
        // bracketing poses (positions linearly, rotation matrices linearly with the direction
        // renormalised), which removes the trigonometry from the per-pulse cost. Over 200 µs an
        // attitude turning at 90°/s moves θ = 3.1e-4 rad, and the blend differs from slerp by at
        // most θ²/16 = 6e-9 rad (12 µm at 2 km; checked numerically over random axes); positions
        // differ from the cubic by a·h²/8 = 5e-8 m at 10 m/s². Knots by global index make a pulse's
        // pose independent of how pulses are batched. The pose at the end of one interval starts
        // the next: one trajectory lookup (~200 cycles) per knot.
        if (n == 0) {
            g.rays.clear();
            g.first_ray.clear();
            return;
        }
        std::size_t hint = 0;
        const std::uint64_t last = first + n;
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
            blend_poses(g.t.data(), g.v[0].data(), g.v[1].data(), g.v[2].data(),
                        std::max(k, first) - first, std::min(k + pose_stride_, last) - first,
                        double(t0), double(t1), entries(m0), entries(m1 - m0),
                        {p0.position.x(), p0.position.y(), p0.position.z()},
                        {dor.x(), dor.y(), dor.z()}, g.origin[0].data(), g.origin[1].data(),
                        g.origin[2].data(), g.direction[0].data(), g.direction[1].data(),
                        g.direction[2].data());
        }
        const std::size_t s_count = subrays_.size();
        g.rays.resize(n * s_count);
        g.first_ray.resize(n);
        // Ray order: one channel over neighbouring groups, sub-rays adjacent (physics.md §4.3:
        // batching one beam over neighbouring azimuths is 4–5× faster than firing order).
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
                // Sub-ray directions in float: rays are float anyway, and the offsets are
                // milliradians, far above float's 6e-8 relative resolution.
                Eigen::Vector3d u, v;
                orthonormal_basis(d, u, v);
                const Eigen::Vector3f df = d.cast<float>(), uf = u.cast<float>(),
                                      vf = v.cast<float>();
                for (std::size_t s = 1; s < s_count; ++s, ++r) {
                    const Eigen::Vector3f ds =
                        (df + tanf_[s].first * uf + tanf_[s].second * vf) * inv_normf_[s];
                    Ray ray = base;
                    ray.dx = ds.x();
                    ray.dy = ds.y();
                    ray.dz = ds.z();
                    g.rays[r] = ray;
                }
            }
        }
    }

  private:
    const sensor::SensorModel& sensor_;
    const core::Trajectory& trajectory_;
    core::Pose mount_;
    GpsTime start_;
    std::vector<sensor::SubRay> subrays_;
    std::vector<std::pair<float, float>> tanf_;  // tangents of the sub-ray offsets
    std::vector<float> inv_normf_;
    std::uint32_t group_;
    std::size_t pose_stride_;  // pulses between exact poses
};

// Sub-ray hit contributing to a return.
struct Contribution {
    double range_m;
    double power_w;
    std::uint32_t sub;  // sub-ray index, to recover the hit
};

struct ChunkResult {
    std::vector<PointRecord> points;         // when the sink encodes: one batch's at a time
    std::unique_ptr<EncodedPoints> encoded;  // the chunk's, when the sink encodes
    RenderStats stats;
};

// A reported return of a batch, waiting for its noise draws.
struct PendingReturn {
    double range_m;     // power-weighted mean range
    double power_w;     // summed received power
    std::uint32_t i;    // pulse within the batch
    std::uint32_t hit;  // index in the batch's hits of the strongest sub-ray: material, normal
    std::uint32_t k;    // index among its pulse's reported returns, nearest first
};

// A worker's buffers for shading one batch: the draws of all its returns are made at once, in
// loops whose iterations are independent (a pulse's draws are one long dependency chain, and
// drawn pulse by pulse they left the core waiting on it).
struct ShadeScratch {
    std::vector<PendingReturn> pending;
    std::vector<std::uint64_t> pulse;
    std::vector<std::uint32_t> block;
    std::array<std::vector<std::uint32_t>, 4> words;
    std::array<std::vector<double>, 4> normals;  // void test, range, jitter x, jitter y
    std::vector<Contribution> contributions;
    std::vector<double> ray_terms;  // per ray: brdf·cos θ·τ²/R², see PulseShader::ray_terms
    std::vector<double> n_laser;    // per pending return: photo-electrons
    std::vector<std::uint16_t> intensity;  // and their calibrated intensity
    std::vector<double> tau1;     // and one-way transmission at their range (for the background)
    std::vector<double> cos_sun;  // and cos θ₂ of the sun on their surface
    std::vector<double> diffuse;  // and that surface's ρ_d/π
    std::vector<double> n_other;  // and background photo-electrons
    std::vector<double> voids;    // and 1 for a void (N_laser < γ·ΔN), else 0
    std::vector<double> range;    // and measured range (noise, resolution)
    std::vector<std::int64_t> steps;         // (that range in resolution steps)
    std::array<std::vector<double>, 3> dir;  // and beam direction, turned by the jitter
    std::array<std::vector<double>, 3> at;   // and point position (local frame)
};

// |cos θ| of a ray on its hit's normal, at most 1.
inline double incidence(const Ray& ray, const Hit& hit) {
    return std::min(1.0, std::abs(double(ray.dx * hit.nx + ray.dy * hit.ny + ray.dz * hit.nz)));
}

// Per ray, brdf·cos θ·τ²/R² (eqs. 2–4 without the per-sensor constants): 0 for a ray without a
// hit in [lo, hi] or seen edge-on (cos θ = 0 or NaN: no return); for a material whose `brdf`
// entry is −1 (a specular lobe) −cos θ·τ²/R², the BRDF to be multiplied in per hit. One loop
// without branches over all rays, so it vectorises, exponential and division included (the
// pointers are `restrict`: GCC will not vectorise the table lookup otherwise). A miss's material
// (kInvalidId) is clamped to a valid index and its term zeroed.
void ray_terms(const Ray* __restrict ray, const Hit* __restrict h, const double* __restrict brdf,
               std::uint32_t last_material, double lo, double hi, double alpha2, std::size_t count,
               double* __restrict out) {
    for (std::size_t r = 0; r < count; ++r) {
        const double f = brdf[std::min(h[r].material, last_material)];
        const double range = h[r].t;
        const bool in_range = (range >= lo) & (range <= hi);  // `&`: no branch
        const double cos_inc = incidence(ray[r], h[r]);
        const double v = f * cos_inc * core::exp_poly(-alpha2 * range) / (range * range);
        const double lit = cos_inc > 0.0 ? v : 0.0;  // two selects: GCC will not vectorise a
        out[r] = in_range ? lit : 0.0;               // select on three combined conditions
    }
}

// tan(x) by its series, for the small jitter angles: exact to double precision for |x| ≤ 1e-2,
// and no libm call per draw.
inline double series_tan(double x) {
    const double x2 = x * x;
    return x * (1.0 + x2 * (1.0 / 3.0 + x2 * (2.0 / 15.0 + x2 * (17.0 / 315.0))));
}

// range[k] += sigma·z[k] (z may be null: no noise), then the nearest multiple of `resolution`
// (0: none) as floor(range/resolution + ½). Branch-free so it vectorises: floor is a conversion
// to int64 (GCC vectorises neither std::floor nor, in the same loop, the conversion back) of the
// value clamped to [0, 1e15], so a range pushed below zero by the noise reads 0. `steps` is
// scratch for n values.
void noisy_ranges(double* __restrict range, const double* __restrict z, double sigma,
                  double resolution, std::size_t n, std::int64_t* __restrict steps) {
    if (z)
        for (std::size_t k = 0; k < n; ++k) range[k] += sigma * z[k];
    if (!(resolution > 0.0)) return;
    const double inv = 1.0 / resolution;
    for (std::size_t k = 0; k < n; ++k) {
        double y = range[k] * inv + 0.5;
        y = y >= 0.0 ? y : 0.0;  // NaN too
        y = y <= 1e15 ? y : 1e15;
        steps[k] = static_cast<std::int64_t>(y);
    }
    for (std::size_t k = 0; k < n; ++k) range[k] = static_cast<double>(steps[k]) * resolution;
}

// Platform jitter (seed 001 eq. 15) of n unit directions: each is turned by the angles σ·zx and
// σ·zy about two axes orthogonal to it (orthonormal_basis, both of its cases computed and one
// selected), so the lateral error grows with range. Branch-free so it vectorises; the tangent is
// the series, exact for angles up to 1e-2 rad: PulseShader::positions redoes larger ones.
void jitter_directions(double* __restrict dx, double* __restrict dy, double* __restrict dz,
                       const double* __restrict zx, const double* __restrict zy, double sigma,
                       std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) {
        const double x = dx[k], y = dy[k], z = dz[k];
        const bool polar = std::abs(z) >= 0.9;
        const double ia = 1.0 / std::sqrt(x * x + y * y);  // unused (maybe inf) when polar
        const double ib = 1.0 / std::sqrt(y * y + z * z);
        const double ux = polar ? 0.0 : y * ia;
        const double uy = polar ? z * ib : -x * ia;
        const double uz = polar ? -y * ib : 0.0;
        const double vx = y * uz - z * uy, vy = z * ux - x * uz, vz = x * uy - y * ux;
        const double tx = series_tan(sigma * zx[k]), ty = series_tan(sigma * zy[k]);
        // |d + tx·u + ty·v| = √(1 + tx² + ty²) for orthonormal (d, u, v).
        const double inv = 1.0 / std::sqrt(1.0 + tx * tx + ty * ty);
        dx[k] = (x + tx * ux + ty * vx) * inv;
        dy[k] = (y + tx * uy + ty * vy) * inv;
        dz[k] = (z + tx * uz + ty * vz) * inv;
    }
}

class PulseShader {
  public:
    PulseShader(const scene::Scene& scene, const sensor::SensorModel& sensor,
                const physics::Environment& env, const RenderOptions& opt)
        : scene_(scene),
          sensor_(sensor),
          env_(env),
          opt_(opt),
          radiometry_(sensor.beam, sensor.receiver, env),
          sun_up_(env.sun.up()),
          to_sun_(env.sun.to_sun_enu()),
          // Sub-ray hits closer than the pulse's range resolution merge into one return.
          separation_m_(0.5 * 299'792'458.0 * sensor.beam.pulse_width_s),
          // Received power of unit weight, range, BRDF, incidence and transmission: every
          // sub-ray's power is this times w·brdf·cos θ·τ²/R² (eqs. 2–4 with the constants folded).
          power_k_(radiometry_.laser_power_w(1.0, 1.0, 1.0, 1.0, 1.0)),
          inv_resolution_(sensor.receiver.range_resolution_m > 0.0
                              ? 1.0 / sensor.receiver.range_resolution_m
                              : 0.0) {
        // Per material, the whole BRDF when it does not depend on incidence (diffuse and retro);
        // −1 marks a specular lobe, evaluated by monostatic_brdf per hit.
        for (const scene::Material& m : scene.materials) {
            const double diffuse = m.reflectance / std::numbers::pi;
            const double f = m.retroreflective ? diffuse + m.retro_gain : diffuse;
            brdf_constant_.push_back(m.specular > 0.0 ? -1.0 : f);
            diffuse_brdf_.push_back(diffuse);
            point_fields_.push_back({m.red, m.green, m.blue, m.classification});
        }
        if (brdf_constant_.empty()) brdf_constant_.push_back(0.0);  // read for misses only
        if (point_fields_.empty()) point_fields_.push_back({});
    }

    void shade(std::uint64_t first, const ChunkGeometry& g, const std::vector<Hit>& hits,
               const std::vector<sensor::SubRay>& subrays, ShadeScratch& scratch,
               ChunkResult& out) const {
        const std::size_t s_count = subrays.size();
        scratch.pending.clear();
        const double alpha = env_.atmosphere.extinction_per_m;
        // Power of each sub-ray per unit brdf·cos θ·τ²/R² (local: one shader serves all threads).
        std::vector<double> weighted_k(s_count);
        for (std::size_t s = 0; s < s_count; ++s) weighted_k[s] = subrays[s].weight * power_k_;
        ray_terms(g, hits, scratch);
        const double* terms = scratch.ray_terms.data();
        if (s_count == 1)
            single_returns(g, hits, terms, weighted_k[0], scratch, out.stats);
        else
            clustered_returns(g, hits, terms, weighted_k, scratch, out.stats);
        out.stats.rays += hits.size();
        draw(first, scratch);
        // Photo-electrons, intensity and (for the background) one-way transmission of every
        // pending return, in loops that vectorise (a logarithm or exponential per point was a
        // library call); voids among them are computed and unused.
        const std::size_t np = scratch.pending.size();
        scratch.n_laser.resize(np);
        scratch.intensity.resize(np);
        for (std::size_t j = 0; j < np; ++j)
            scratch.n_laser[j] = radiometry_.laser_electrons(scratch.pending[j].power_w);
        if (sun_up_ || env_.path_radiance_w_m2_sr_um > 0.0) {
            scratch.tau1.resize(np);
            for (std::size_t j = 0; j < np; ++j)
                scratch.tau1[j] = core::exp_poly(-alpha * scratch.pending[j].range_m);
        }
        opt_.intensity.to_u16_many(scratch.n_laser.data(), np, scratch.intensity.data());
        detect(hits, scratch);
        positions(g, scratch);
        emit_points(first, g, hits, scratch, out);
    }

  private:
    // A return: sub-ray hits merged into one echo.
    struct Return {
        double range_m = 0;          // power-weighted mean range
        double power_w = 0;          // summed received power
        std::uint32_t best_sub = 0;  // the strongest sub-ray: its hit gives material, normal
    };

    // Sub-ray hits spread over more than c·τ/2: sorted by range and split where the gap exceeds
    // it (two surfaces closer than that blend into one echo); then the reported ones are emitted.
    void split_returns(std::uint32_t i, std::uint32_t first_hit, std::span<Contribution> contrib,
                       ShadeScratch& scratch) const {
        // Insertion sort by range: a handful of sub-rays.
        for (std::size_t a = 1; a < contrib.size(); ++a) {
            const Contribution c = contrib[a];
            std::size_t b = a;
            for (; b > 0 && (contrib[b - 1].range_m > c.range_m ||
                             (contrib[b - 1].range_m == c.range_m && contrib[b - 1].sub > c.sub));
                 --b)
                contrib[b] = contrib[b - 1];
            contrib[b] = c;
        }
        struct Sum {
            double rp = 0, p = 0, best_p = -1;
            std::uint32_t best_sub = 0;
        };
        Sum sums[8];
        int count = 0;
        double last_range = -1e300;
        for (const Contribution& c : contrib) {
            if (count == 0 || c.range_m - last_range > separation_m_) {
                if (count == 8) break;
                ++count;
            }
            Sum& r = sums[count - 1];
            r.rp += c.range_m * c.power_w;
            r.p += c.power_w;
            if (c.power_w > r.best_p) {
                r.best_p = c.power_w;
                r.best_sub = c.sub;
            }
            last_range = c.range_m;
        }
        // Which returns are reported: the strongest when one is kept, else the nearest ones.
        auto to_return = [&](const Sum& r) {
            return Return{r.p > 0 ? r.rp / r.p : contrib.front().range_m, r.p, r.best_sub};
        };
        Return chosen[8];
        std::size_t kept = 0;
        const int max_returns = std::clamp(sensor_.receiver.max_returns, 1, 8);
        if (max_returns == 1) {
            int best = 0;
            for (int k = 1; k < count; ++k)
                if (sums[k].p > sums[best].p) best = k;
            chosen[kept++] = to_return(sums[best]);
        } else {
            for (int k = 0; k < count && kept < std::size_t(max_returns); ++k)
                chosen[kept++] = to_return(sums[k]);
        }
        add_returns(i, first_hit, std::span<const Return>(chosen, kept), scratch);
    }

    // Several sub-rays per pulse: their hits merge into returns (split_returns when they spread
    // over more than c·τ/2).
    void clustered_returns(const ChunkGeometry& g, const std::vector<Hit>& hits,
                           const double* terms, const std::vector<double>& weighted_k,
                           ShadeScratch& scratch, RenderStats& stats) const {
        const std::size_t n = g.specs.size();
        const std::size_t s_count = weighted_k.size();
        const auto& rx = sensor_.receiver;
        scratch.contributions.resize(s_count);
        Contribution* buffer = scratch.contributions.data();  // a pulse's: buffer[0, nc)
        for (std::size_t i = 0; i < n; ++i) {
            const Hit* h = &hits[g.first_ray[i]];
            const Ray* ray = &g.rays[g.first_ray[i]];
            const double* term = terms + g.first_ray[i];
            std::size_t nc = 0;
            bool any_close = false;
            // The one-return aggregates, accumulated on the way (in sub-ray order, as a split
            // into several returns would sum them): range span, power-weighted range, power,
            // and the strongest sub-ray (the first of equals).
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            double sum_rp = 0, sum_p = 0, best_p = -1;
            std::uint32_t best_sub = 0;
            for (std::size_t s = 0; s < s_count; ++s) {
                if (!h[s].hit()) continue;
                const double range = h[s].t;
                if (range < rx.min_range_m) {
                    any_close = true;
                    continue;
                }
                if (range > rx.max_range_m) continue;
                double t = term[s];
                if (t < 0.0) {  // a specular lobe: the BRDF depends on incidence
                    const double cos_inc = incidence(ray[s], h[s]);
                    t = -t * physics::monostatic_brdf(scene_.materials[h[s].material], cos_inc);
                }
                const double p = weighted_k[s] * t;
                buffer[nc++] = {range, p, static_cast<std::uint32_t>(s)};
                lo = std::min(lo, range);
                hi = std::max(hi, range);
                sum_rp += range * p;
                sum_p += p;
                if (p > best_p) {
                    best_p = p;
                    best_sub = static_cast<std::uint32_t>(s);
                }
            }
            stats.pulses++;
            if (nc == 0) {
                if (any_close)
                    stats.too_close++;
                else
                    stats.misses++;
                continue;
            }
            // Usual case: every sub-ray hit lies within c·τ/2 of the others, so no gap can
            // split them and one return takes them all, without sorting.
            const Return one{sum_p > 0 ? sum_rp / sum_p : buffer[0].range_m, sum_p, best_sub};
            const auto ii = static_cast<std::uint32_t>(i);
            if (hi - lo <= separation_m_)
                add_returns(ii, g.first_ray[i], std::span<const Return>(&one, 1), scratch);
            else
                split_returns(ii, g.first_ray[i], std::span<Contribution>(buffer, nc), scratch);
        }
    }

    // One sub-ray per pulse: its hit, if within the receiver's ranges, is the pulse's only
    // return. Hits and misses alternate unpredictably, so this runs without branches: every pulse
    // writes a candidate and only one with a return advances the count.
    void single_returns(const ChunkGeometry& g, const std::vector<Hit>& hits, const double* terms,
                        double k, ShadeScratch& scratch, RenderStats& stats) const {
        const std::size_t n = g.specs.size();
        const double lo = sensor_.receiver.min_range_m, hi = sensor_.receiver.max_range_m;
        scratch.pending.resize(n);
        PendingReturn* out = scratch.pending.data();
        std::size_t np = 0;
        std::uint64_t close = 0, missed = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t r = g.first_ray[i];
            const double range = hits[r].t;  // +inf on a miss
            const bool near = range < lo;
            const bool in = !near & (range <= hi);
            out[np] = {range, k * terms[r], static_cast<std::uint32_t>(i), r, 0};
            np += in;
            close += near;
            missed += !near & !in;
        }
        scratch.pending.resize(np);
        for (PendingReturn& p : scratch.pending) {
            if (p.power_w < 0.0) {  // a specular lobe (see ray_terms): its BRDF per hit
                const Hit& h = hits[p.hit];
                const double t =
                    -terms[p.hit] * physics::monostatic_brdf(scene_.materials[h.material],
                                                             incidence(g.rays[p.hit], h));
                p.power_w = k * t;
            }
        }
        stats.pulses += n;
        stats.too_close += close;
        stats.misses += missed;
    }

    // Queues a pulse's reported returns (nearest first) for drawing and emission.
    void add_returns(std::uint32_t i, std::uint32_t first_hit, std::span<const Return> returns,
                     ShadeScratch& scratch) const {
        std::uint32_t k = 0;
        for (const Return& r : returns)
            scratch.pending.push_back({r.range_m, r.power_w, i, first_hit + r.best_sub, k++});
    }

    // Per ray of the batch, brdf·cos θ·τ²/R²: see ray_terms() above.
    void ray_terms(const ChunkGeometry& g, const std::vector<Hit>& hits,
                   ShadeScratch& scratch) const {
        scratch.ray_terms.resize(hits.size());
        render::ray_terms(g.rays.data(), hits.data(), brdf_constant_.data(),
                          static_cast<std::uint32_t>(brdf_constant_.size() - 1),
                          sensor_.receiver.min_range_m, sensor_.receiver.max_range_m,
                          2.0 * env_.atmosphere.extinction_per_m, hits.size(),
                          scratch.ray_terms.data());
    }

    // The normals of every pending return. Return k of a pulse uses Philox block k of the pulse's
    // stream 0, one word per draw (void test, range, jitter x, jitter y), so a pulse's draws do
    // not depend on which of its returns were voids.
    void draw(std::uint64_t first, ShadeScratch& scratch) const {
        if (!opt_.noise) return;
        const std::size_t np = scratch.pending.size();
        scratch.pulse.resize(np);
        scratch.block.resize(np);
        for (std::size_t j = 0; j < np; ++j) {
            scratch.pulse[j] = first + scratch.pending[j].i;
            scratch.block[j] = scratch.pending[j].k;
        }
        for (auto& w : scratch.words) w.resize(np);
        core::philox_blocks(opt_.seed, 0, scratch.pulse.data(), scratch.block.data(), np,
                            {scratch.words[0].data(), scratch.words[1].data(),
                             scratch.words[2].data(), scratch.words[3].data()});
        const bool need[4] = {true, sensor_.noise.range_sigma_m > 0.0,
                              sensor_.noise.jitter_sigma_rad > 0.0,
                              sensor_.noise.jitter_sigma_rad > 0.0};
        for (std::size_t w = 0; w < 4; ++w) {
            if (!need[w]) continue;
            scratch.normals[w].resize(np);
            core::normals_of_words(scratch.words[w].data(), np, scratch.normals[w].data());
        }
    }

    // Background photo-electrons and the void test (eqs. 6–13) of every pending return, batched.
    void detect(const std::vector<Hit>& hits, ShadeScratch& scratch) const {
        const std::size_t np = scratch.pending.size();
        scratch.n_other.assign(np, 0.0);
        scratch.voids.resize(np);
        if (sun_up_ || env_.path_radiance_w_m2_sr_um > 0.0) {
            scratch.cos_sun.resize(np);
            scratch.diffuse.resize(np);
            for (std::size_t j = 0; j < np; ++j) {
                const Hit& h = hits[scratch.pending[j].hit];
                scratch.cos_sun[j] =
                    sun_up_ ? h.nx * to_sun_.x() + h.ny * to_sun_.y() + h.nz * to_sun_.z() : 0.0;
                scratch.diffuse[j] = diffuse_brdf_[h.material];
            }
            radiometry_.background_electrons_many(scratch.diffuse.data(), scratch.cos_sun.data(),
                                                  scratch.tau1.data(), np, scratch.n_other.data());
        }
        radiometry_.voids_many(scratch.n_laser.data(), scratch.n_other.data(),
                               opt_.noise ? scratch.normals[0].data() : nullptr, np,
                               scratch.voids.data());
    }

    // Measured range and point position of every pending return (voids included, unused).
    void positions(const ChunkGeometry& g, ShadeScratch& scratch) const {
        const std::size_t np = scratch.pending.size();
        scratch.range.resize(np);
        scratch.steps.resize(np);
        for (int a = 0; a < 3; ++a) {
            scratch.dir[a].resize(np);
            scratch.at[a].resize(np);
        }
        // Each return's pulse direction (and below origin), gathered so the loops read arrays.
        for (std::size_t j = 0; j < np; ++j) {
            const std::uint32_t i = scratch.pending[j].i;
            scratch.range[j] = scratch.pending[j].range_m;
            for (int a = 0; a < 3; ++a) scratch.dir[a][j] = g.direction[a][i];
        }
        const double jitter = opt_.noise ? sensor_.noise.jitter_sigma_rad : 0.0;
        const double range_sigma = opt_.noise ? sensor_.noise.range_sigma_m : 0.0;
        noisy_ranges(scratch.range.data(), range_sigma > 0.0 ? scratch.normals[1].data() : nullptr,
                     range_sigma, inv_resolution_ > 0.0 ? sensor_.receiver.range_resolution_m : 0.0,
                     np, scratch.steps.data());
        if (jitter > 0.0) {
            const double* zx = scratch.normals[2].data();
            const double* zy = scratch.normals[3].data();
            jitter_directions(scratch.dir[0].data(), scratch.dir[1].data(), scratch.dir[2].data(),
                              zx, zy, jitter, np);
            // Angles beyond the series' range (σ of milliradians and more): the exact tangent.
            for (std::size_t j = 0; j < np; ++j) {
                if (std::abs(jitter * zx[j]) <= 1e-2 && std::abs(jitter * zy[j]) <= 1e-2) continue;
                const Eigen::Vector3d d = g.direction_of(scratch.pending[j].i);
                Eigen::Vector3d u, v;
                orthonormal_basis(d, u, v);
                const double tx = std::tan(jitter * zx[j]), ty = std::tan(jitter * zy[j]);
                const Eigen::Vector3d e =
                    (d + tx * u + ty * v) * (1.0 / std::sqrt(1.0 + tx * tx + ty * ty));
                for (int a = 0; a < 3; ++a) scratch.dir[a][j] = e[a];
            }
        }
        for (std::size_t j = 0; j < np; ++j)
            for (int a = 0; a < 3; ++a) scratch.at[a][j] = g.origin[a][scratch.pending[j].i];
        for (int a = 0; a < 3; ++a) {
            const double* __restrict d = scratch.dir[a].data();
            const double* __restrict range = scratch.range.data();
            double* __restrict at = scratch.at[a].data();
            for (std::size_t j = 0; j < np; ++j) at[j] += range[j] * d[j];
        }
    }

    // The point records of the pending returns that are not voids. Every pending return is
    // written and only one that is not a void advances the count, so the loop has no branch on
    // the void test and reads the pulse and material fields by index; return numbers follow per
    // pulse.
    void emit_points(std::uint64_t first, const ChunkGeometry& g, const std::vector<Hit>& hits,
                     const ShadeScratch& scratch, ChunkResult& out) const {
        const std::size_t np = scratch.pending.size();
        const std::size_t base = out.points.size();
        out.points.resize(base + np);
        PointRecord* pts = out.points.data() + base;
        const PendingReturn* pending = scratch.pending.data();
        const double* voids = scratch.voids.data();
        std::size_t kept = 0;
        for (std::size_t j = 0; j < np; ++j) {
            const PendingReturn& r = pending[j];
            const sensor::PulseSpec& spec = g.specs[r.i];
            const PointFields& m = point_fields_[hits[r.hit].material];
            PointRecord& pt = pts[kept];
            pt.x = scratch.at[0][j];
            pt.y = scratch.at[1][j];
            pt.z = scratch.at[2][j];
            pt.t = opt_.start + core::Nanos(spec.t_ns);
            pt.pulse = first + r.i;
            pt.range_m = static_cast<float>(scratch.range[j]);
            pt.scan_angle_deg = spec.scan_angle_deg;
            pt.azimuth_deg = spec.azimuth_deg;
            pt.n_laser = scratch.n_laser[j];
            pt.intensity = scratch.intensity[j];
            pt.channel = spec.channel;
            pt.point_source_id = sensor_.point_source_id;
            pt.red = m.red;
            pt.green = m.green;
            pt.blue = m.blue;
            pt.classification = m.classification;
            pt.scan_direction = spec.scan_direction;
            pt.edge_of_flight_line = spec.edge_of_flight_line;
            kept += voids[j] == 0.0;
        }
        out.points.resize(base + kept);
        // Each pulse's points in order, nearest first; a pulse whose returns were all voids
        // counts as one void.
        PointRecord* pt = pts;
        for (std::size_t j = 0; j < np;) {
            const std::uint32_t i = pending[j].i;
            std::size_t n = 0;
            for (; j < np && pending[j].i == i; ++j) n += voids[j] == 0.0;
            if (n == 0) out.stats.voids++;
            for (std::size_t k = 0; k < n; ++k, ++pt) {
                pt->return_number = static_cast<std::uint8_t>(k + 1);
                pt->number_of_returns = static_cast<std::uint8_t>(n);
            }
        }
        out.stats.points += kept;
    }

    // What a point record takes from its material, packed (scene::Material is a large struct).
    struct PointFields {
        std::uint16_t red, green, blue;
        std::uint8_t classification;
    };

    const scene::Scene& scene_;
    const sensor::SensorModel& sensor_;
    const physics::Environment& env_;
    const RenderOptions& opt_;
    physics::Radiometry radiometry_;
    bool sun_up_;
    Eigen::Vector3d to_sun_;
    double separation_m_;
    double power_k_;
    double inv_resolution_;
    std::vector<double> brdf_constant_;      // by material index: ρ_d/π (+ retro gain), or −1
    std::vector<double> diffuse_brdf_;       // by material index: ρ_d/π (the sunlit background)
    std::vector<PointFields> point_fields_;  // by material index
};

double thread_cpu_s() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// A worker's CPU time per stage over one chunk. The thread's CPU clock is a system call (~2 600
// cycles a read on the development VM: 5 reads per 2 048-pulse batch come to ~6 cycles a pulse),
// so it is read once per chunk and split between the stages by the steady clock (a vDSO read).
class StageClock {
  public:
    enum Stage { kRays, kTrace, kShade, kOutput, kStages };
    StageClock() : cpu0_(thread_cpu_s()), last_(std::chrono::steady_clock::now()) {}
    void lap(Stage s) {
        const auto now = std::chrono::steady_clock::now();
        wall_[s] += now - last_;
        last_ = now;
    }
    void add_to(RenderStats& stats) const {
        std::chrono::steady_clock::duration wall{};
        for (const auto& w : wall_) wall += w;
        const double k =
            wall.count() > 0 ? (thread_cpu_s() - cpu0_) / static_cast<double>(wall.count()) : 0.0;
        stats.cpu_rays_s += k * static_cast<double>(wall_[kRays].count());
        stats.cpu_trace_s += k * static_cast<double>(wall_[kTrace].count());
        stats.cpu_shade_s += k * static_cast<double>(wall_[kShade].count());
        stats.cpu_output_s += k * static_cast<double>(wall_[kOutput].count());
    }

  private:
    double cpu0_;
    std::chrono::steady_clock::time_point last_;
    std::array<std::chrono::steady_clock::duration, kStages> wall_{};  // integer ticks
};

void accumulate(RenderStats& into, const RenderStats& s) {
    into.cpu_rays_s += s.cpu_rays_s;
    into.cpu_trace_s += s.cpu_trace_s;
    into.cpu_shade_s += s.cpu_shade_s;
    into.cpu_output_s += s.cpu_output_s;
    into.pulses += s.pulses;
    into.points += s.points;
    into.misses += s.misses;
    into.voids += s.voids;
    into.too_close += s.too_close;
    into.rays += s.rays;
}

}  // namespace

std::size_t chunk_pulses(const sensor::SensorModel& sensor, std::size_t requested) {
    const std::size_t group = std::max<std::uint32_t>(1, sensor.scan->group_size());
    return std::max<std::size_t>(group, requested / group * group);
}

std::size_t chunks_for_lead(const sensor::SensorModel& sensor, std::size_t requested,
                            core::Nanos lead) {
    const std::uint64_t pulses = sensor.scan->pulse_count(lead);
    const std::uint64_t c = chunk_pulses(sensor, requested);  // ≥ 1: one firing group at least
    return static_cast<std::size_t>(std::max<std::uint64_t>(1, (pulses + c - 1) / c));
}

std::vector<Ray> pipeline_rays(const sensor::SensorModel& sensor,
                               const core::Trajectory& trajectory, const core::Mount& mount,
                               core::GpsTime start, std::uint64_t first, std::size_t n) {
    ChunkBuilder builder(sensor, trajectory, mount, start);
    ChunkGeometry g;
    std::vector<Ray> rays;
    const std::size_t batch = trace_batch_pulses(sensor);
    for (std::size_t done = 0; done < n; done += batch) {
        builder.build(first + done, std::min(batch, n - done), g);
        rays.insert(rays.end(), g.rays.begin(), g.rays.end());
    }
    return rays;
}

std::size_t trace_batch_pulses(const sensor::SensorModel& sensor) {
    return chunk_pulses(sensor, kTraceBatchPulses);
}

RenderStats render(const scene::Scene& scene, const Renderer& renderer,
                   const sensor::SensorModel& sensor, const core::Trajectory& trajectory,
                   const core::Mount& mount, const physics::Environment& env,
                   const RenderOptions& opt, PointSink& sink, const ProgressFn& progress,
                   const std::atomic<bool>* stop) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t total = sensor.scan->pulse_count(opt.duration);
    const std::size_t chunk = chunk_pulses(sensor, opt.chunk_pulses);
    const std::size_t batch = trace_batch_pulses(sensor);
    const std::uint64_t chunks = (total + chunk - 1) / chunk;
    int threads = opt.threads > 0
                      ? opt.threads
                      : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

    const ChunkBuilder builder(sensor, trajectory, mount, opt.start);
    const PulseShader shader(scene, sensor, env, opt);
    const bool encodes = sink.new_encoded() != nullptr;

    // Ordered hand-over: workers fill slots, this thread writes them in chunk order, so the
    // output is identical for any thread count. At most `window` chunks are in flight.
    const std::uint64_t window =
        opt.window_chunks > 0 ? opt.window_chunks : static_cast<std::uint64_t>(threads) * 2 + 2;
    std::mutex mu;
    std::condition_variable cv_done, cv_space;
    std::deque<std::unique_ptr<ChunkResult>> slots;  // slots[k] = chunk written_ + k
    // Written chunks go back to a pool: fresh multi-megabyte vectors per chunk cost more in page
    // faults than the physics.
    std::vector<std::unique_ptr<ChunkResult>> pool_free;
    std::uint64_t written = 0, next = 0;
    bool abort = false;
    std::exception_ptr error;

    auto worker = [&]() {
        pthread_setname_np(pthread_self(), "mirage-render");  // for top, perf and ps
        ChunkGeometry g;
        std::vector<Hit> hits;
        ShadeScratch scratch;
        for (;;) {
            std::uint64_t c;
            {
                std::unique_lock lk(mu);
                cv_space.wait(lk,
                              [&] { return abort || next >= chunks || next < written + window; });
                if (abort || next >= chunks) return;
                if (stop && stop->load()) {
                    abort = true;
                    cv_done.notify_all();
                    return;
                }
                c = next++;
            }
            std::unique_ptr<ChunkResult> result;
            {
                std::lock_guard lk(mu);
                if (!pool_free.empty()) {
                    result = std::move(pool_free.back());
                    pool_free.pop_back();
                }
            }
            if (!result) result = std::make_unique<ChunkResult>();
            result->points.clear();
            result->stats = {};
            if (encodes && !result->encoded) result->encoded = sink.new_encoded();
            if (result->encoded) result->encoded->clear();
            try {
                const std::uint64_t first = c * chunk;
                const std::size_t n =
                    static_cast<std::size_t>(std::min<std::uint64_t>(chunk, total - first));
                // Traced in batches that keep rays and hits in cache; the chunk (the unit of
                // hand-over between threads) spans several, so threads wake less often.
                StageClock clock;
                for (std::size_t done = 0; done < n; done += batch) {
                    const std::size_t m = std::min(batch, n - done);
                    builder.build(first + done, m, g);
                    hits.resize(g.rays.size());
                    clock.lap(StageClock::kRays);
                    renderer.intersect(g.rays, hits);
                    clock.lap(StageClock::kTrace);
                    shader.shade(first + done, g, hits, builder.subrays(), scratch, *result);
                    clock.lap(StageClock::kShade);
                    if (encodes) {
                        sink.encode(result->points, *result->encoded);
                        result->points.clear();
                        clock.lap(StageClock::kOutput);
                    }
                }
                clock.add_to(result->stats);
            } catch (...) {
                std::lock_guard lk(mu);
                if (!error) error = std::current_exception();
                abort = true;
                cv_done.notify_all();
                cv_space.notify_all();
                return;
            }
            std::lock_guard lk(mu);
            const std::uint64_t k = c - written;
            if (slots.size() <= k) slots.resize(k + 1);
            slots[k] = std::move(result);
            cv_done.notify_all();
        }
    };

    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads));
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);

    RenderStats stats;
    for (;;) {
        std::unique_ptr<ChunkResult> ready;
        {
            std::unique_lock lk(mu);
            cv_done.wait(lk, [&] {
                return written >= chunks || (!slots.empty() && slots.front()) ||
                       (abort && (slots.empty() || !slots.front()));
            });
            if (written >= chunks) break;
            if (slots.empty() || !slots.front()) break;  // aborted and nothing ready in order
            ready = std::move(slots.front());
            slots.pop_front();
            ++written;  // with the pop, so slots[k] stays chunk written + k for the workers
        }
        try {
            const double c0 = thread_cpu_s();
            if (encodes)
                sink.write_encoded(*ready->encoded);
            else
                sink.write(ready->points);
            sink.pulses_done(std::min<std::uint64_t>(written * chunk, total));
            stats.cpu_output_s += thread_cpu_s() - c0;
        } catch (...) {
            std::lock_guard lk(mu);
            if (!error) error = std::current_exception();
            abort = true;
            cv_space.notify_all();
            break;
        }
        accumulate(stats, ready->stats);
        {
            std::lock_guard lk(mu);
            pool_free.push_back(std::move(ready));
        }
        cv_space.notify_all();
        if (progress) {
            stats.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            progress(stats);
        }
    }
    {
        std::lock_guard lk(mu);
        abort = true;
    }
    cv_space.notify_all();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return stats;
}

// The environment and options are copied: PulseShader keeps references, and callers may pass
// temporaries. Scene, renderer and sensor must outlive the WindowRenderer.
struct WindowRenderer::Impl {
    Impl(const scene::Scene& scene, const Renderer& r, const sensor::SensorModel& s,
         const core::Mount& m, const physics::Environment& e, const RenderOptions& o)
        : renderer(r), sensor(s), mount(m), env(e), opt(o), shader(scene, s, env, opt) {}
    const Renderer& renderer;
    const sensor::SensorModel& sensor;
    core::Mount mount;
    physics::Environment env;
    RenderOptions opt;
    PulseShader shader;  // after env and opt, which it refers to
    ChunkGeometry g;
    std::vector<Hit> hits;
    ShadeScratch scratch;
    ChunkResult result;
};

WindowRenderer::WindowRenderer(const scene::Scene& scene, const Renderer& renderer,
                               const sensor::SensorModel& sensor, const core::Mount& mount,
                               const physics::Environment& env, const RenderOptions& opt)
    : impl_(std::make_unique<Impl>(scene, renderer, sensor, mount, env, opt)) {}

WindowRenderer::~WindowRenderer() = default;

void WindowRenderer::render(const core::Trajectory& trajectory, std::uint64_t first, std::size_t n,
                            std::vector<core::PointRecord>& out, RenderStats& stats) {
    Impl& m = *impl_;
    const ChunkBuilder builder(m.sensor, trajectory, m.mount, m.opt.start);
    m.result.points.swap(out);
    m.result.stats = {};
    const std::size_t batch = trace_batch_pulses(m.sensor);
    for (std::size_t done = 0; done < n; done += batch) {
        const std::size_t k = std::min(batch, n - done);
        builder.build(first + done, k, m.g);
        m.hits.resize(m.g.rays.size());
        m.renderer.intersect(m.g.rays, m.hits);
        m.shader.shade(first + done, m.g, m.hits, builder.subrays(), m.scratch, m.result);
    }
    m.result.points.swap(out);
    accumulate(stats, m.result.stats);
}

}  // namespace mirage::render
