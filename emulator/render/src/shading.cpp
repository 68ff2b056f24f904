// SPDX-License-Identifier: Apache-2.0
// Shading: radiometry, detection and noise of a batch's pending returns, then their points.
#include "shading.hpp"

#include <numbers>

#include "basis.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/exp_poly.hpp"
#include "mirage/core/rng.hpp"
#include "mirage/physics/speckle.hpp"
#include "mirage/sensor/presets.hpp"

namespace mirage::render {
namespace {

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
// (0: none) as floor(range/resolution + ½) of the value clamped to [0, 1e15], so a range pushed
// below zero by the noise reads 0. Branch-free so it vectorises (std::floor and the selects do
// under -fno-trapping-math, cmake/mirage_warnings.cmake).
void noisy_ranges(double* __restrict range, const double* __restrict z, double sigma,
                  double resolution, std::size_t n) {
    if (z)
        for (std::size_t k = 0; k < n; ++k) range[k] += sigma * z[k];
    if (!(resolution > 0.0)) return;
    const double inv = 1.0 / resolution;
    for (std::size_t k = 0; k < n; ++k) {
        double y = range[k] * inv + 0.5;
        y = y >= 0.0 ? y : 0.0;  // NaN too
        y = y <= 1e15 ? y : 1e15;
        range[k] = std::floor(y) * resolution;
    }
}

// Platform jitter (docs/physics.md eq. (15)) of n unit directions: each is turned by the angles
// σ·zx and σ·zy about two axes orthogonal to it (orthonormal_basis, both of its cases computed and
// one selected), so the lateral error grows with range. Branch-free so it vectorises; the tangent
// is the series, exact for angles up to 1e-2 rad: PulseShader::exact_jitter redoes larger ones.
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

}  // namespace

PulseShader::PulseShader(const Setup& setup)
    : scene_(setup.scene),
      renderer_(setup.renderer),
      sensor_(setup.sensor),
      env_(setup.env),
      opt_(setup.options),
      radiometry_(sensor_.beam, sensor_.receiver, env_),
      sun_up_(env_.sun.up()),
      to_sun_(env_.sun.to_sun_enu()),
      // Sub-ray hits closer than the pulse's range resolution merge into one return.
      separation_m_(0.5 * 299'792'458.0 * sensor_.beam.pulse_width_s),
      // Angle between neighbouring sub-rays (the footprint's ring spacing, beam radius / k).
      cell_rad_(sensor_.beam.sub_rays > 1
                    ? 0.5 * sensor_.beam.divergence_rad * sensor_.beam.footprint_radius /
                          sensor::ring_count(sensor_.beam.sub_rays)
                    : 0.0),
      // Received power of unit weight, range, BRDF, incidence and transmission: every sub-ray's
      // power is this times w·brdf·cos θ·τ²/R² (eqs. 2–4 with the constants folded).
      power_k_(radiometry_.laser_power_w(1.0, 1.0, 1.0, 1.0, 1.0)),
      inv_resolution_(sensor_.receiver.range_resolution_m > 0.0
                          ? 1.0 / sensor_.receiver.range_resolution_m
                          : 0.0) {
    // Per material, the whole BRDF when it does not depend on incidence (diffuse and retro); −1
    // marks a specular lobe, evaluated by monostatic_brdf per hit.
    for (const scene::Material& m : scene_.materials) {
        const double diffuse = m.reflectance / std::numbers::pi;
        const double f = m.retroreflective ? diffuse + m.retro_gain : diffuse;
        brdf_constant_.push_back(m.specular > 0.0 ? -1.0 : f);
        diffuse_brdf_.push_back(diffuse);
        point_fields_.push_back({m.red, m.green, m.blue, m.classification});
        // With diffuse bounces every surface that reflects sends the path on (paths.cpp).
        const bool goes_on =
            m.continues() || (sensor_.receiver.diffuse_bounces > 0 && m.reflectance > 0.0);
        continues_.push_back(goes_on ? 1 : 0);
        continues_any_ |= goes_on;
    }
    if (continues_.empty()) continues_.push_back(0);
    // An echo from the atmosphere: LAS class 18 (high noise), no colour.
    volume_fields_ = static_cast<std::uint32_t>(point_fields_.size());
    point_fields_.push_back({0, 0, 0, 18});
    if (brdf_constant_.empty()) brdf_constant_.push_back(0.0);  // read for misses only
    if (point_fields_.empty()) point_fields_.push_back({});
    if (sensor_.detector == sensor::DetectorKind::Linear) {
        // The pulse: the measured shape, or a Gaussian of the beam's FWHM (time-resolved.md §4).
        const std::string source = "sensor '" + sensor_.name + "'";
        const auto& b = sensor_.beam;
        const auto shape = b.pulse_t_ns.empty()
                               ? sensor::PulseShape::gaussian(b.pulse_width_s * 1e9, source)
                               : sensor::PulseShape::tabulated(b.pulse_t_ns, b.pulse_power, source);
        sigma_p_ns_ = shape.sigma_ns();
        matched_ = !b.pulse_t_ns.empty();
        linear_.emplace(sensor_.linear, source);
        synth_.emplace(shape, 1.0 / sensor_.linear.sample_rate_gsps,
                       source + ": detector.sample_rate_gsps");
        merge_window_ps_ = matched_ ? 1e3 * synth_->period_ns() / physics::WaveformSynth::kSubSteps
                                    : 500.0 * sigma_p_ns_;
        if (sensor_.linear.timing == sensor::EchoTiming::ConstantFraction)
            cfd_offset_ns_ = calibrate_cfd();
    }
    speckle_m_ = sensor::speckle_cells(sensor_);
    bounces_ = sensor_.receiver.diffuse_bounces;
    {  // the pixel's field of view and its share of the spot (docs/physics.md eq. 4′)
        const auto& rx = sensor_.receiver;
        const double f = rx.f_number * rx.aperture_diameter_m;
        fov_half_rad_ = std::min(0.5 * sensor::ifov_rad(rx), 0.5 * std::numbers::pi);
        fov_cos_ = std::cos(fov_half_rad_);
        const double t = std::tan(0.5 * sensor_.beam.divergence_rad);
        const double spot = std::numbers::pi * t * t, pix = rx.detector_area_m2 / (f * f);
        if (spot > 0.0 && pix > 0.0) nee_scale_ = spot / std::min(spot, pix);
        const double reach = 0.5 * sensor_.beam.divergence_rad * sensor_.beam.footprint_radius;
        image_cut_ = env_.turbulence.on() && pix >= spot && reach <= fov_half_rad_;
    }
    if (sensor_.beam.adaptive_footprint) {
        const auto probes = footprint_probes(std::size_t(sensor_.beam.sub_rays));
        for (std::uint32_t s = 0; s < probes.size(); ++s)
            (probes[s] ? probe_at_ : rest_at_).push_back(s);
        m2_ = footprint_m2();
        const double t =
            std::tan(0.5 * sensor_.beam.divergence_rad * sensor_.beam.footprint_radius);
        max_offset2_ = t * t;
    }
    share_ = sensor_.array.share;
    check_recording();
    init_volume();
    init_geiger();
}

// Waveforms are recorded from the linear detector's digitiser, at most kMaxWaveformSamples per
// pulse (a chunk's samples are indexed by 32 bits).
void PulseShader::check_recording() const {
    const std::uint32_t n = opt_.waveform_samples;
    if (n == 0) return;
    const std::string source = "sensor '" + sensor_.name + "'";
    if (!linear_)
        throw mirage::ConfigError(source + ": recording waveforms needs detector.kind: linear");
    if (n > kMaxWaveformSamples)
        throw mirage::ConfigError(source + ": " + std::to_string(n) +
                                  " waveform samples per pulse (at most " +
                                  std::to_string(kMaxWaveformSamples) + ")");
}

// One Philox normal of the pulse's stream 3, so the energy does not depend on what else the
// pulse draws. Applies with or without detector noise: it is the laser's, not the detector's.
double PulseShader::energy_factor(std::uint64_t pulse) const {
    // An array's pixel-pulse carries its pixel's share of the laser pulse (ArrayScan order).
    const double share = share_.empty() ? 1.0 : double(share_[pulse % share_.size()]);
    const double sigma = sensor_.beam.energy_sigma;
    if (!(sigma > 0.0)) return share;
    core::PulseRng rng(opt_.seed, pulse, kEnergyStream);
    return share * std::max(0.0, 1.0 + sigma * rng.normal());
}

// The discrete detector's pending returns scaled by their pulse's energy factor and, with
// speckle, each by its own factor, drawn in return order from the pulse's stream 4.
void PulseShader::vary_returns(std::uint64_t first, ShadeScratch& scratch) const {
    const bool speckle = speckle_on();
    if (!(sensor_.beam.energy_sigma > 0.0) && !speckle && share_.empty()) return;
    std::uint32_t last = 0xFFFFFFFFu;
    double f = 1.0;
    std::optional<core::PulseRng> rng;
    for (PendingReturn& p : scratch.pending) {
        if (p.i != last) {
            f = energy_factor(first + (last = p.i));
            if (speckle) rng.emplace(opt_.seed, first + p.i, kSpeckleStream);
        }
        p.power_w *= speckle ? f * physics::speckle_factor(*rng, speckle_m_) : f;
    }
}

std::vector<double> PulseShader::weighted_k(const std::vector<sensor::SubRay>& subrays) const {
    std::vector<double> k(subrays.size());
    for (std::size_t s = 0; s < subrays.size(); ++s) k[s] = subrays[s].weight * power_k_;
    return k;
}

void PulseShader::shade(const RayBatch& g, std::vector<Hit>& hits,
                        const std::vector<sensor::SubRay>& subrays, ShadeScratch& scratch,
                        ShadedPoints& out) const {
    scratch.pending.clear();
    // Power of each sub-ray per unit brdf·cos θ·τ²/R² (local: one shader serves all threads).
    const std::vector<double> k = weighted_k(subrays);
    // With continuations their hits follow the batch's own in `hits`, and returns index the
    // longer vector. Without, everything below is the first-hit path as it always was.
    scratch.paths = trace_paths(g, hits, scratch, out.stats);
    const RayView rays = rays_of(g, scratch.paths ? &scratch.path : nullptr);
    ray_terms(g, hits, scratch);
    const double* terms = scratch.ray_terms.data();
    out.stats.rays += g.traced;
    if (geiger_) {  // photon events: no noise draws, voids or intensity of their own
        geiger_returns(g, hits, terms, k, scratch, out);
        event_points(g, scratch);
        emit_points(g, hits, scratch, out);
        return;
    }
    if (linear_)
        waveform_returns(g, hits, terms, k, scratch, out);
    else if (subrays.size() == 1 && !scratch.paths && g.plane.empty())
        single_returns(g, hits, terms, k[0], scratch, out.stats);
    else
        clustered_returns(g, hits, rays, terms, k, scratch, out.stats);
    if (!linear_) vary_returns(g.first, scratch);  // the waveform detector's: per arrival
    draw(g.first, scratch);
    electrons(g, scratch);
    detect(hits, scratch);
    positions(g, scratch);
    emit_points(g, hits, scratch, out);
}

// Per ray brdf·cos θ·τ²/R² (see ray_terms() above): the batch's own rays, then (scratch.paths)
// the continuations', whose terms carry their paths' weights.
void PulseShader::ray_terms(const RayBatch& g, const std::vector<Hit>& hits,
                            ShadeScratch& scratch) const {
    scratch.ray_terms.resize(hits.size());
    const bool profile = env_.atmosphere.scale_height_m > 0.0;
    const double alpha2 = profile ? 0.0 : 2.0 * env_.atmosphere.extinction_per_m;
    const auto kernel = [&](const Ray* rays, std::size_t from, std::size_t count) {
        render::ray_terms(rays, hits.data() + from, brdf_constant_.data(),
                          static_cast<std::uint32_t>(brdf_constant_.size() - 1),
                          sensor_.receiver.min_range_m, sensor_.receiver.max_range_m, alpha2, count,
                          scratch.ray_terms.data() + from);
    };
    const PathScratch* paths = scratch.paths ? &scratch.path : nullptr;
    const std::size_t own = paths ? paths->own : hits.size();
    if (g.plane.empty()) {
        kernel(g.rays.data(), 0, own);
    } else {  // adaptive footprints: a pulse done by its probes reads its central ray's only
        const std::size_t per = own / g.block_done.size();
        std::size_t run = 0;  // first ray of the current run of sampled pulses
        for (std::size_t b = 0; b < g.block_done.size(); ++b) {
            if (!g.block_done[b]) continue;
            kernel(g.rays.data() + run, run, b * per - run);
            kernel(g.rays.data() + b * per, b * per, 1);
            run = (b + 1) * per;
        }
        kernel(g.rays.data() + run, run, own - run);
    }
    if (paths) {
        kernel(paths->rays.data(), own, paths->rays.size());
        for (std::size_t k = 0; k < paths->rays.size(); ++k)
            scratch.ray_terms[own + k] *= paths->weight[k];
        if (!paths->nee.empty()) next_event_terms(hits, alpha2, scratch);
    }
    if (profile) slant_transmission(rays_of(g, paths), hits, scratch);
}

// An open path's hit (past a diffuse bounce, paths.cpp) sends its light straight to the
// receiver: weight·(ρ_d/π)·cos θ_r/R²·τ over the whole path (τ² at half of it, the hit's range),
// taken by the receiver inside its field of view without the pixel's share of the spot (eq. 4′).
void PulseShader::next_event_terms(const std::vector<Hit>& hits, double alpha2,
                                   ShadeScratch& scratch) const {
    const PathScratch& p = scratch.path;
    const double lo = sensor_.receiver.min_range_m, hi = sensor_.receiver.max_range_m;
    for (std::size_t k = 0; k < p.rays.size(); ++k) {
        if (p.nee[k] < 0.0) continue;
        const Hit& h = hits[p.own + k];
        const bool seen = h.hit() && h.t >= lo && h.t <= hi && p.nee[k] > 0.0;
        scratch.ray_terms[p.own + k] = seen ? p.weight[k] * diffuse_brdf_[h.material] * p.nee[k] *
                                                  nee_scale_ * core::exp_poly(-alpha2 * h.t)
                                            : 0.0;
    }
}

// An extinction profile: each term times the two-way transmittance of its path, from the ray's
// origin to its hit in a straight line (a mirrored path: its last segment's mean α over the whole
// length).
void PulseShader::slant_transmission(const RayView& rays, const std::vector<Hit>& hits,
                                     ShadeScratch& scratch) const {
    for (std::size_t e = 0; e < hits.size(); ++e) {
        double& term = scratch.ray_terms[e];
        if (term == 0.0 || !hits[e].hit()) continue;  // (a miss's term may be unset)
        // An open path's light goes out and back by different ways: no profile along it.
        if (e >= rays.n && !scratch.path.nee.empty() && scratch.path.nee[e - rays.n] >= 0.0)
            continue;
        const double base = e < rays.n ? 0.0 : scratch.path.base[e - rays.n];
        const Ray& r = rays[e];
        const double z1 = r.oz + (hits[e].t - base) * r.dz;
        term *= std::exp(-2.0 * env_.atmosphere.optical_depth(r.oz, z1, hits[e].t));
    }
}

// Photo-electrons, intensity and (for the background) one-way transmission of every pending
// return, in loops that vectorise (a logarithm or exponential per point was a library call);
// voids among them are computed and unused.
void PulseShader::electrons(const RayBatch& g, ShadeScratch& scratch) const {
    const std::size_t np = scratch.pending.size();
    scratch.n_laser.resize(np);
    scratch.intensity.resize(np);
    for (std::size_t j = 0; j < np; ++j)
        scratch.n_laser[j] = radiometry_.laser_electrons(scratch.pending[j].power_w);
    if (sun_up_ || env_.path_radiance_w_m2_sr_um > 0.0) {
        const double alpha = env_.atmosphere.extinction_per_m;
        scratch.tau1.resize(np);
        for (std::size_t j = 0; j < np; ++j)
            scratch.tau1[j] = core::exp_poly(-alpha * scratch.pending[j].range_m);
        if (env_.atmosphere.scale_height_m > 0.0)
            for (std::size_t j = 0; j < np; ++j) {
                const std::uint32_t i = scratch.pending[j].i;
                const double r = scratch.pending[j].range_m, z0 = g.origin[2][i];
                scratch.tau1[j] =
                    std::exp(-env_.atmosphere.optical_depth(z0, z0 + r * g.direction[2][i], r));
            }
    }
    opt_.intensity.to_u16_many(scratch.n_laser.data(), np, scratch.intensity.data());
}

// The normals of every pending return. Return k of a pulse uses Philox block k of the pulse's
// stream 0, one word per draw (void test, range, jitter x, jitter y), so a pulse's draws do not
// depend on which of its returns were voids.
void PulseShader::draw(std::uint64_t first, ShadeScratch& scratch) const {
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
                        {scratch.words[0].data(), scratch.words[1].data(), scratch.words[2].data(),
                         scratch.words[3].data()});
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
void PulseShader::detect(const std::vector<Hit>& hits, ShadeScratch& scratch) const {
    const std::size_t np = scratch.pending.size();
    scratch.n_other.assign(np, 0.0);
    scratch.voids.resize(np);
    if (linear_) {  // the waveform's threshold has decided already
        std::fill(scratch.voids.begin(), scratch.voids.end(), 0.0);
        return;
    }
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
void PulseShader::positions(const RayBatch& g, ShadeScratch& scratch) const {
    const std::size_t np = scratch.pending.size();
    scratch.range.resize(np);
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
                 np);
    if (jitter > 0.0) {
        jitter_directions(scratch.dir[0].data(), scratch.dir[1].data(), scratch.dir[2].data(),
                          scratch.normals[2].data(), scratch.normals[3].data(), jitter, np);
        exact_jitter(g, jitter, scratch);
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

// Jitter angles beyond the series' range (σ of milliradians and more): the exact tangent.
void PulseShader::exact_jitter(const RayBatch& g, double jitter, ShadeScratch& scratch) const {
    const double* zx = scratch.normals[2].data();
    const double* zy = scratch.normals[3].data();
    for (std::size_t j = 0; j < scratch.pending.size(); ++j) {
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

// The point records of the pending returns that are not voids, with return numbers per pulse
// (nearest first); a pulse whose returns were all voids counts as one void.
void PulseShader::emit_points(const RayBatch& g, const std::vector<Hit>& hits,
                              const ShadeScratch& scratch, ShadedPoints& out) const {
    const std::size_t np = scratch.pending.size();
    const std::size_t base = out.points.size();
    out.points.resize(base + np);
    const std::size_t kept = write_records(g, hits, scratch, out.points.data() + base);
    out.points.resize(base + kept);
    const PendingReturn* pending = scratch.pending.data();
    const double* voids = scratch.voids.data();
    core::PointRecord* pt = out.points.data() + base;
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

// Every pending return is written to pts[] and only one that is not a void advances the count,
// so the loop has no branch on the void test and reads the pulse and material fields by index.
// Returns the count.
std::size_t PulseShader::write_records(const RayBatch& g, const std::vector<Hit>& hits,
                                       const ShadeScratch& scratch, core::PointRecord* pts) const {
    const PendingReturn* pending = scratch.pending.data();
    const double* voids = scratch.voids.data();
    const EchoFields* echo = scratch.echo_fields.empty() ? nullptr : scratch.echo_fields.data();
    const std::uint8_t* event = geiger_ ? scratch.event_kind.data() : nullptr;
    std::size_t kept = 0;
    for (std::size_t j = 0; j < scratch.pending.size(); ++j) {
        const PendingReturn& r = pending[j];
        const sensor::PulseSpec& spec = g.specs[r.i];
        const PointFields& m =
            point_fields_[r.hit == kVolumeHit ? volume_fields_ : hits[r.hit].material];
        core::PointRecord& pt = pts[kept];
        pt.x = scratch.at[0][j];
        pt.y = scratch.at[1][j];
        pt.z = scratch.at[2][j];
        pt.t = opt_.start + core::Nanos(spec.t_ns);
        pt.pulse = g.first + r.i;
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
        pt.pixel = spec.pixel;
        pt.event = event ? event[j] : 0;
        if (echo) {
            pt.amplitude = echo[j].amplitude;
            pt.echo_width_ns = echo[j].width_ns;
            pt.deviation = echo[j].deviation;
            pt.wave = echo[j].wave;
            pt.wave_location_ps = echo[j].wave_location_ps;
            pt.beam_dx = static_cast<float>(scratch.dir[0][j]);
            pt.beam_dy = static_cast<float>(scratch.dir[1][j]);
            pt.beam_dz = static_cast<float>(scratch.dir[2][j]);
        }
        kept += voids[j] == 0.0;
    }
    return kept;
}

}  // namespace mirage::render
