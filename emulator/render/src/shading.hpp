// SPDX-License-Identifier: Apache-2.0
// Shading: a traced batch's hits -> returns (clustering, returns.cpp) -> radiometry, detection,
// noise -> point records (shading.cpp).
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "carry_chain.hpp"
#include "mirage/core/point.hpp"
#include "mirage/physics/crosstalk.hpp"
#include "mirage/physics/first_event.hpp"
#include "mirage/physics/geiger.hpp"
#include "mirage/physics/linear_detector.hpp"
#include "mirage/physics/radiometry.hpp"
#include "mirage/physics/waveform.hpp"
#include "mirage/render/render_stats.hpp"
#include "mirage/render/setup.hpp"
#include "mirage/sensor/pulse_shape.hpp"
#include "ray_batch.hpp"

namespace mirage::render {

// Sub-ray hit contributing to a return.
struct Contribution {
    double range_m;
    double power_w;
    std::uint32_t sub;          // sub-ray index, to recover the hit
    double half_depth_m = 0.0;  // half the range depth of the sub-ray's patch (split_returns)
};

// A reported return of a batch, waiting for its noise draws.
struct PendingReturn {
    double range_m;     // power-weighted mean range
    double power_w;     // summed received power
    std::uint32_t i;    // pulse within the batch
    std::uint32_t hit;  // index in the batch's hits of the strongest sub-ray: material, normal
    std::uint32_t k;    // index among its pulse's reported returns, nearest first
};

// A batch's paths beyond the first hit (paths.cpp; docs/time-resolved.md §5). The batch's own
// hits stay where they are and the continuations' hits follow them in the same vector (entry
// e = own + k); here, per continuation k: its ray, the two-way weight of the surfaces passed
// before it, the path length before its ray's origin, the sub-ray it descends from, a path code
// (the roulette's counter) and its pulse. Hit::t is the whole one-way path.
struct PathScratch {
    std::size_t own = 0;  // the batch's own entries
    std::vector<Ray> rays;
    std::vector<double> weight;
    std::vector<double> base;
    std::vector<std::uint32_t> sub, code, pulse;
    // Per continuation: whether its path is open (past a diffuse bounce: its light reaches the
    // receiver by the next event from each hit, not back along the path) and its bounces so far;
    // for an open one's hit, cos θ_r/R² toward the receiver (0: outside the field of view or
    // hidden), −1 for a closed one.
    std::vector<std::uint8_t> open, bounces;
    std::vector<double> nee;
    // next_events' shadow rays: their rays, hits, continuations and cos θ_r/R².
    std::vector<Ray> shadow;
    std::vector<Hit> blocked;
    std::vector<std::uint32_t> shadow_of;
    std::vector<double> shadow_term;
    std::vector<std::uint32_t> first,
        order;  // continuations of pulse i (entries): order[first[i], first[i+1])
    std::vector<Ray> round_rays;
    std::vector<Hit> round_hits;
    std::size_t most = 0;  // the most continuations of one pulse

    void start(std::size_t own_entries) {
        own = own_entries;
        rays.clear();
        weight.clear();
        base.clear();
        sub.clear();
        code.clear();
        pulse.clear();
        open.clear();
        bounces.clear();
        nee.clear();
        round_rays.clear();
    }
    std::span<const std::uint32_t> of_pulse(std::uint32_t i) const {
        return {order.data() + first[i], order.data() + first[i + 1]};
    }
};

// The ray of entry e: the batch's own, then the continuations'.
struct RayView {
    const Ray* own;
    std::size_t n;
    const Ray* more;
    const Ray& operator[](std::size_t e) const { return e < n ? own[e] : more[e - n]; }
};

// What a continuation starts from: its parent entry's ray, hit and path state.
struct PathParent {
    Ray ray;
    Hit hit;
    double weight, base;
    std::uint32_t sub, code, pulse;
    std::uint8_t open = 0, bounces = 0;
};

// Samples [j0, j1) digitised as one waveform: arrivals [a, b) and, where it overlaps, the
// atmosphere's volume backscatter (waveform_returns.cpp). Its samples sit from `at` in the
// batch's waveform buffers, padded to whole Philox blocks of four.
struct SampleGroup {
    std::int64_t j0, j1;
    std::size_t a, b;
    std::size_t at = 0;
    std::size_t size() const { return static_cast<std::size_t>(j1 - j0); }
    std::size_t blocks() const { return (size() + 3) / 4; }  // Philox blocks of its noise
    std::size_t end() const { return at + 4 * blocks(); }    // where its padded samples end
};

// One pulse of a batch whose waveform the linear detector digitises: its arrivals [a, b) and
// groups [g0, g1) in the batch's buffers, its floor (background and dark photo-electrons per
// sample) and energy factor.
struct PulseWave {
    std::uint32_t i;
    std::size_t a, b, g0, g1;
    double floor_pe, energy;
};

// Philox stream of each pulse's energy factor (0: discrete returns, 1: waveform noise, 2: the
// paths' roulette).
inline constexpr std::uint32_t kEnergyStream = 3;
inline constexpr std::uint32_t kSpeckleStream = 4;    // each return's speckle factor, in order
inline constexpr std::uint32_t kWanderStream = 5;     // the beam's wander, two normals
inline constexpr std::uint32_t kBounceStream = 6;     // a diffuse bounce's direction, per path
inline constexpr std::uint32_t kImageStream = 7;      // the return's image wander, two normals
inline constexpr std::uint32_t kGeigerStream = 8;     // a Geiger-mode pixel's photon events
inline constexpr std::uint32_t kCrosstalkStream = 9;  // and the crosstalk its detections make

// An event of a frame under crosstalk (geiger_returns.cpp): the event, its pixel in the frame,
// and a sequence number that orders equal times and pixels.
struct FrameEvent {
    physics::GeigerEvent e;
    std::uint32_t p, seq;
    bool operator<(const FrameEvent& o) const {
        if (e.t_ns != o.e.t_ns) return e.t_ns < o.e.t_ns;
        return p != o.p ? p < o.p : seq < o.seq;
    }
};

// A batch's Geiger-mode events (geiger_returns.cpp): pulse i's events at
// [event_at[i], event_at[i + 1]), its arrivals likewise, its expected signal photo-electrons.
// Crosstalk's, reused frame by frame: the frame's own events in time order, a heap of the events
// crosstalk makes, the events kept; per pixel its re-arming time, its kept events and its random
// stream (index into rngs); the batch's events after crosstalk, as `events` and `event_at`.
struct GeigerBatch {
    std::vector<physics::GeigerEvent> events;
    std::vector<physics::Arrival> arrivals;
    std::vector<std::size_t> event_at, arrival_at;
    std::vector<double> expected;
    std::span<const physics::Arrival> arrivals_of(std::size_t i) const {
        return {arrivals.data() + arrival_at[i], arrival_at[i + 1] - arrival_at[i]};
    }
    std::vector<FrameEvent> own, made, kept;
    std::vector<double> armed;
    std::vector<std::uint32_t> count, rng_of;
    std::vector<core::PulseRng> rngs;
    std::vector<physics::GeigerEvent> after;
    std::vector<std::size_t> after_at;
    // A pixel that reports its first event only: each pulse's event (t_ns = +inf: none), which
    // crosstalk_first changes in place; per pixel of the frame, the neighbours it fires (from
    // block 0 of its stream 9, drawn for the frame at once) and the draw's scratch.
    std::vector<physics::GeigerEvent> first;
    std::vector<std::uint8_t> fires;
    std::vector<physics::CrosstalkFiring> firing;
    std::vector<std::uint32_t> blocks;
    std::vector<std::uint64_t> pulses;
    std::array<std::vector<std::uint32_t>, 4> words;
    // Each pixel-pulse's block 0 of stream 8 (first_levels) and its first event's level.
    std::array<std::vector<std::uint32_t>, 4> first_words;
    std::vector<double> level;
    std::vector<physics::SignalRun> runs;  // a pixel's arrivals as rows (first_event)
    // A free-running array (geiger_carry.cpp): per pixel-pulse of the frame being drawn, when its
    // own draw re-arms it; per pixel, the dead time carried into the window of frame
    // carry_frame[p] (ns into it; ≤ 0: armed at its start).
    std::vector<double> own_end;
    std::vector<double> carry;
    std::vector<std::uint64_t> carry_frame;
    std::uint64_t take_frame = 0;  // > 0: the carry into this frame is still to come (CarryChain)
};

// PendingReturn::hit of an echo from the atmosphere itself (no surface).
inline constexpr std::uint32_t kVolumeHit = 0xFFFFFFFFu;

// What the waveform detector adds to a point (see core::PointRecord).
struct EchoFields {
    float amplitude = 0, width_ns = 0, deviation = 0, wave_location_ps = 0;
    std::uint32_t wave = core::PointRecord::kNoWave;
};

// An echo whose deviation from its fit is still to be computed (fit_deviations): its first
// sample in the batch's counts, its samples, its fit and baseline, and its point's EchoFields
// (kNoField while it has none).
struct DeviationJob {
    static constexpr std::size_t kNoField = ~std::size_t{0};
    std::size_t at = 0;
    std::int64_t first = 0, end = 0;
    double time_ns = 0, amplitude = 0, sigma_ns = 0, baseline = 0;
    std::size_t field = kNoField;
};

// Samples a render may record per pulse (RenderOptions::waveform_samples).
inline constexpr std::uint32_t kMaxWaveformSamples = 65536;

// Echoes a waveform detector reports per pulse, at most (LAS return numbers go to 15; the
// receiver keeps up to sensor::kMaxReturns of them).
inline constexpr std::size_t kMaxEchoes = 8;

// A worker's buffers for shading one batch: the draws of all its returns are made at once, in
// loops whose iterations are independent (a pulse's draws are one long dependency chain, and
// drawn pulse by pulse they left the core waiting on it).
struct ShadeScratch {
    std::vector<PendingReturn> pending;
    std::vector<std::uint64_t> pulse;
    std::vector<std::uint32_t> block;
    std::array<std::vector<std::uint32_t>, 4> words;
    std::vector<std::uint32_t> sample_words;     // the waveform's words in sample order
    std::array<std::vector<double>, 4> normals;  // void test, range, jitter x, jitter y
    std::vector<Contribution> contributions;
    std::vector<double> ray_terms;  // per ray: brdf·cos θ·τ²/R², see ray_terms() in shading.cpp
    std::vector<double> n_laser;    // per pending return: photo-electrons
    std::vector<std::uint16_t> intensity;  // and their calibrated intensity
    std::vector<double> tau1;     // and one-way transmission at their range (for the background)
    std::vector<double> cos_sun;  // and cos θ₂ of the sun on their surface
    std::vector<double> diffuse;  // and that surface's ρ_d/π
    std::vector<double> n_other;  // and background photo-electrons
    std::vector<double> voids;    // and 1 for a void (N_laser < γ·ΔN), else 0
    std::vector<double> range;    // and measured range (noise, resolution)
    std::array<std::vector<double>, 3> dir;  // and beam direction, turned by the jitter
    std::array<std::vector<double>, 3> at;   // and point position (local frame)
    // The linear-mode detector's (waveform_returns.cpp): a pulse's arrivals as they are made,
    // then the batch's pulses, arrivals and sample groups, digitised in one pass (wave: expected
    // photo-electrons, wave_z: noise, counts) and searched for echoes pulse by pulse.
    std::vector<physics::Arrival> arrivals, sorted;  // (sorted: sort_by_delay's space)
    PathScratch path;
    bool paths = false;  // this batch has continuations (path.* valid)
    std::vector<PulseWave> pulse_waves;
    std::vector<physics::Arrival> wave_arrivals;
    std::vector<SampleGroup> groups;
    std::vector<double> wave, wave_z, counts, pulse_template;
    std::vector<double> gap_wave, gap_z, gap_counts;  // a recorded window's samples between groups
    std::vector<physics::Echo> echoes;
    std::int64_t wave_first = 0;  // the pulse's first digitised sample
    // Per pending return (linear detector only): amplitude, width, deviation, recorded waveform.
    std::vector<EchoFields> echo_fields;
    std::vector<DeviationJob> deviation_jobs;
    std::vector<double> fit_x;  // the jobs' samples (fit_deviations)
    // A render recording waveforms (waveform_record.cpp): the pulse's window, NaN where no
    // arrival group's samples were digitised.
    std::vector<double> record;
    // The Geiger-mode detector's (geiger_returns.cpp): a pulse's signal bins, event rate and
    // events; per pending return its event kind (PointRecord::event) and its pulse's expected
    // signal photo-electrons.
    std::vector<physics::SignalBin> signal_bins;
    physics::EventRate rate;
    std::vector<physics::GeigerEvent> events;
    GeigerBatch geiger;
    std::vector<std::uint8_t> event_kind;
    std::vector<double> expected_pe;
};

// What shading appends to: point records in pulse order, the digitised samples they refer to
// (PointRecord::wave; a render recording waveforms only), and the counts.
struct ShadedPoints {
    std::vector<core::PointRecord> points;
    std::vector<std::uint32_t> samples;
    RenderStats stats;
};

// |cos θ| of a ray on its hit's normal, at most 1.
inline double incidence(const Ray& ray, const Hit& hit) {
    return std::min(1.0, std::abs(double(ray.dx * hit.nx + ray.dy * hit.ny + ray.dz * hit.nz)));
}

// Turns a traced batch into points. One shader serves all threads (shade() is const); it refers
// to the setup's scene, sensor, environment and options, so the setup must outlive it.
class PulseShader {
  public:
    explicit PulseShader(const Setup& setup);

    // `hits` (the batch's, one per ray) gains the hits of the paths' continuations.
    // The batch's first hits into `hits`; with turbulence (and noise on) each pulse's beam is
    // first turned by its wander and traced again (beam_wander.cpp).
    void trace(RayBatch& g, std::vector<Hit>& hits) const;
    void shade(const RayBatch& g, std::vector<Hit>& hits,
               const std::vector<sensor::SubRay>& subrays, ShadeScratch& scratch,
               ShadedPoints& out) const;
    // render()'s chunks of a free-running Geiger-mode array: before the chunk starting at pulse
    // `first`, the dead time carried into it (waits for the worker of the chunk before); after
    // the chunk ending before pulse `next`, the dead time it carries on. No-ops otherwise, and a
    // caller that draws frames in order on one scratch needs neither.
    void begin_chunk(std::uint64_t first, ShadeScratch& scratch) const;
    void end_chunk(std::uint64_t next, ShadeScratch& scratch) const;
    // A worker failed: wakes the ones waiting in begin_chunk().
    void abort_chunks() const;
    // Pulse i's arrivals (docs/time-resolved.md §2): one per sub-ray hit within the receiver's
    // ranges, expected photo-electrons and two-way delay, unsorted. Returns whether a sub-ray hit
    // closer than the minimum range.
    // `paths` (when the batch has continuations) adds theirs, whose hits follow the batch's.
    bool pulse_arrivals(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                        const std::vector<double>& weighted_k, std::uint32_t i,
                        std::vector<physics::Arrival>& out,
                        const PathScratch* paths = nullptr) const;
    // Per ray brdf·cos θ·τ²/R² into scratch.ray_terms (shading.cpp), and each sub-ray's power
    // per unit of it.
    // With scratch.paths, also the continuations' (their hits after the batch's own).
    void ray_terms(const RayBatch& g, const std::vector<Hit>& hits, ShadeScratch& scratch) const;
    std::vector<double> weighted_k(const std::vector<sensor::SubRay>& subrays) const;
    // paths.cpp: continuations of a batch's paths into s.path (their hits appended to `hits`);
    // false when none.
    bool trace_paths(const RayBatch& g, std::vector<Hit>& hits, ShadeScratch& s,
                     RenderStats& stats) const;

  private:
    // A return: sub-ray hits merged into one echo.
    struct Return {
        double range_m = 0;          // power-weighted mean range
        double power_w = 0;          // summed received power
        std::uint32_t best_sub = 0;  // the strongest sub-ray: its hit gives material, normal
    };
    // A pulse's sub-ray hits within the receiver's ranges (buffer[0, count)), and the aggregates
    // of one return taking them all.
    struct PulseHits {
        std::size_t count = 0;
        bool any_close = false;
        double lo = 0, hi = 0, sum_rp = 0, sum_p = 0;
        std::uint32_t best_sub = 0;
    };
    // Power-weighted sums of one return while sub-ray hits are grouped.
    struct ReturnSum {
        double rp = 0, p = 0, best_p = -1;
        std::uint32_t best_sub = 0;
    };

    // returns.cpp: sub-ray hits -> pending returns.
    void single_returns(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                        double k, ShadeScratch& scratch, RenderStats& stats) const;
    void clustered_returns(const RayBatch& g, const std::vector<Hit>& hits, const RayView& rays,
                           const double* terms, const std::vector<double>& weighted_k,
                           ShadeScratch& scratch, RenderStats& stats) const;
    // h and term point at the pulse's first sub-ray (batch entry r); its continuations (paths,
    // when the batch has them) at entries e, relative index e − r.
    PulseHits gather_hits(const Hit* h, const RayView& rays, const double* term,
                          const std::vector<double>& weighted_k, Contribution* buffer,
                          const PathScratch* paths, std::uint32_t r, std::uint32_t i) const;
    void set_patch_depths(const Hit* h, const RayView& rays, std::uint32_t r,
                          std::span<Contribution> contrib) const;
    void split_returns(std::uint32_t i, std::uint32_t first_hit, std::span<Contribution> contrib,
                       ShadeScratch& scratch) const;
    int group_returns(std::span<const Contribution> contrib, ReturnSum (&sums)[8]) const;
    void add_returns(std::uint32_t i, std::uint32_t first_hit, std::span<const Return> returns,
                     ShadeScratch& scratch) const;

    // waveform_returns.cpp: the linear-mode detector's returns.
    void waveform_returns(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                          const std::vector<double>& weighted_k, ShadeScratch& scratch,
                          ShadedPoints& out) const;
    void merge_close_arrivals(std::vector<physics::Arrival>& arrivals) const;
    void plane_arrivals(const PlaneFootprint& f, double central_pe, std::uint32_t hit,
                        std::vector<physics::Arrival>& out) const;
    double floor_pe_per_sample(const std::vector<Hit>& hits,
                               std::span<const physics::Arrival> arrivals) const;
    double background_per_ns(const std::vector<Hit>& hits,
                             std::span<const physics::Arrival> arrivals) const;
    bool gather_pulse(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                      const std::vector<double>& weighted_k, std::uint32_t i,
                      ShadeScratch& scratch) const;
    void digitise_batch(std::uint64_t first_pulse, ShadeScratch& scratch) const;
    void detect_pulse(std::uint64_t first_pulse, const PulseWave& w, ShadeScratch& scratch,
                      ShadedPoints& out) const;
    void detect_group(const SampleGroup& g, double floor_pe, std::size_t& found,
                      ShadeScratch& scratch) const;
    // geiger_returns.cpp: the Geiger-mode detector's events.
    struct GeigerGate {
        double open_ns = 0, bin_ns = 1;  // the gate opens this long after emission
        std::size_t bins = 0;
        // Free-running: the rate's bins run to the next pulse's window (`period_ns` on), and
        // detections before report_ns (the range gate) are reported.
        bool free_running = false;
        double period_ns = 0, report_ns = 0;
        physics::GeigerPixel pixel;
        double dark_per_ns = 0;
        double shape_lo = 0;  // where the pulse's support starts, ns from its centroid
        // tabulate_bin_weights(): the pulse's share per bin, `span` bins per offset row.
        std::size_t span = 0;
        std::vector<double> weights;
        std::vector<double> shares;  // each row's running sums, in order (physics::SignalRun)
    };
    void init_geiger();
    void tabulate_bin_weights(const sensor::PulseShape& shape, double hi, GeigerGate& g) const;
    void geiger_returns(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                        const std::vector<double>& weighted_k, ShadeScratch& scratch,
                        ShadedPoints& out) const;
    bool pixel_events(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                      const std::vector<double>& weighted_k, std::uint32_t i, double armed_from,
                      ShadeScratch& scratch) const;
    void draw_events(double level, double armed_from, const physics::GeigerPixel& pixel,
                     core::PulseRng& rng, ShadeScratch& scratch) const;
    double carried(std::uint64_t pulse, const GeigerBatch& b) const;
    void take_carry(GeigerBatch& b) const;
    void carry_on(std::uint64_t first, std::uint32_t i0, std::uint32_t end, bool crosstalk,
                  GeigerBatch& b) const;
    void first_blocks(std::uint64_t first, std::uint32_t n, std::uint32_t stream, GeigerBatch& b,
                      std::array<std::vector<std::uint32_t>, 4>& words) const;
    void first_levels(std::uint64_t first, std::uint32_t n, GeigerBatch& b) const;
    bool first_event(std::span<const physics::Arrival> arrivals, double noise_per_bin, double level,
                     const physics::GeigerPixel& pixel, const std::array<std::uint32_t, 4>& block0,
                     ShadeScratch& scratch) const;
    void crosstalk(const RayBatch& g, std::uint32_t i0, GeigerBatch& b) const;
    void crosstalk_first(const RayBatch& g, std::uint32_t i0, std::uint32_t n,
                         GeigerBatch& b) const;
    std::array<std::uint32_t, 4> crosstalk_hits(std::uint64_t frame_pulse, std::uint32_t p,
                                                std::uint32_t n, GeigerBatch& b) const;
    void by_pixel(GeigerBatch& b) const;
    struct ArrivalRow {
        std::int64_t k0;  // the gate's bin of the row's first entry
        const double* w;  // GeigerGate::span shares
    };
    ArrivalRow arrival_row(const physics::Arrival& a) const;
    void event_rate(std::span<const physics::Arrival> arrivals, double noise_per_bin,
                    ShadeScratch& scratch) const;
    double geiger_noise_per_ns(const std::vector<Hit>& hits,
                               std::span<const physics::Arrival> arrivals) const;
    void add_event(std::uint32_t i, std::uint32_t k, const physics::GeigerEvent& e,
                   std::span<const physics::Arrival> arrivals, ShadeScratch& scratch) const;
    void event_points(const RayBatch& g, ShadeScratch& scratch) const;
    // volume.cpp: the atmosphere's backscatter in the waveform.
    void init_volume();
    void convolve_volume();
    void sample_groups(std::span<const physics::Arrival> arr, std::size_t base,
                       std::vector<SampleGroup>& groups) const;
    void add_volume(std::int64_t j0, std::span<double> wave, double scale) const;
    bool in_volume(double time_ns) const;
    void draw_normals(std::uint64_t pulse, std::size_t n, std::uint32_t block,
                      std::vector<double>& z, ShadeScratch& scratch) const;
    void normals_of_blocks(std::size_t blocks, std::vector<double>& z, ShadeScratch& scratch) const;
    void add_echoes(std::uint32_t i, std::span<const physics::Arrival> arrivals, std::uint32_t wave,
                    ShadeScratch& scratch) const;
    double matched_time_ns(const physics::Echo& e, const double* counts, double baseline,
                           ShadeScratch& scratch) const;
    void time_echoes(const SampleGroup& g, double baseline, std::size_t from, std::size_t to,
                     ShadeScratch& scratch) const;
    double calibrate_cfd() const;
    EchoFields echo_fields(const physics::Echo& e, std::uint32_t wave,
                           std::int64_t wave_first) const;
    void fit_deviations(ShadeScratch& scratch) const;
    void fit_gaussians(ShadeScratch& scratch) const;
    void check_recording() const;
    // The pulse's energy relative to the sensor's (beam.energy_sigma; 1 when it is 0).
    double energy_factor(std::uint64_t pulse) const;
    void vary_returns(std::uint64_t first, ShadeScratch& scratch) const;
    // Speckle applies with noise on, when the sensor has speckle cells (time-resolved.md §6).
    bool speckle_on() const { return opt_.noise && speckle_m_ >= 1.0; }
    // beam_wander.cpp: each pulse's beam turned and spread by the turbulence at its first range,
    // and the pixel's axis turned by its image's wander.
    void wander(RayBatch& g, const std::vector<Hit>& hits) const;
    bool inside_fov(const RayBatch& g, std::size_t i, double margin) const;
    void cut_by_fov(const RayBatch& g, std::vector<Hit>& hits) const;
    // adaptive_footprint.cpp: probes first, a plane's footprint in closed form.
    double footprint_m2() const;
    void trace_footprints(RayBatch& g, std::vector<Hit>& hits) const;
    void trace_part(RayBatch& g, std::vector<Hit>& hits, bool probes) const;
    PlaneFootprint plane_footprint(const RayBatch& g, const std::vector<Hit>& hits,
                                   std::size_t i) const;
    bool on_plane(const RayBatch& g, const std::vector<Hit>& hits, std::uint32_t r) const;
    // paths.cpp: continuations of a batch's paths into scratch.path; false when none.
    bool any_continuing(const std::vector<Hit>& hits) const;
    bool continues(const Hit& h) const;
    bool trace_round(PathScratch& p, std::vector<Hit>& hits, RenderStats& stats) const;
    void spawn(std::uint64_t first_pulse, const PathParent& parent, PathScratch& p,
               RenderStats& stats) const;
    void index_by_pulse(std::size_t pulses, PathScratch& p) const;
    void push_continuation(std::uint64_t first_pulse, const PathParent& q, const Ray& r,
                           double fraction, double base, std::uint32_t kind, PathScratch& p,
                           RenderStats& stats) const;
    void add_bounce(std::uint64_t first_pulse, const PathParent& q, PathScratch& p,
                    RenderStats& stats) const;
    void next_events(const RayBatch& g, std::vector<Hit>& hits, PathScratch& p) const;
    // waveform_record.cpp: the digitised window a render records per pulse with returns.
    void record_group(const SampleGroup& g, ShadeScratch& scratch) const;
    std::uint32_t record_pulse(std::uint64_t pulse, const PulseWave& w, ShadeScratch& scratch,
                               std::vector<std::uint32_t>& samples) const;

    // shading.cpp: pending returns -> points.
    void electrons(const RayBatch& g, ShadeScratch& scratch) const;
    void next_event_terms(const std::vector<Hit>& hits, double alpha2, ShadeScratch& scratch) const;
    void slant_transmission(const RayView& rays, const std::vector<Hit>& hits,
                            ShadeScratch& scratch) const;
    RayView rays_of(const RayBatch& g, const PathScratch* paths) const {
        return {g.rays.data(), paths ? paths->own : g.rays.size(),
                paths ? paths->rays.data() : nullptr};
    }
    void draw(std::uint64_t first, ShadeScratch& scratch) const;
    void detect(const std::vector<Hit>& hits, ShadeScratch& scratch) const;
    void positions(const RayBatch& g, ShadeScratch& scratch) const;
    void exact_jitter(const RayBatch& g, double jitter, ShadeScratch& scratch) const;
    void emit_points(const RayBatch& g, const std::vector<Hit>& hits, const ShadeScratch& scratch,
                     ShadedPoints& out) const;
    std::size_t write_records(const RayBatch& g, const std::vector<Hit>& hits,
                              const ShadeScratch& scratch, core::PointRecord* pts) const;

    // What a point record takes from its material, packed (scene::Material is a large struct).
    struct PointFields {
        std::uint16_t red, green, blue;
        std::uint8_t classification;
    };

    const scene::Scene& scene_;
    const Renderer& renderer_;  // continuation rounds (paths.cpp)
    const sensor::SensorModel& sensor_;
    const physics::Environment& env_;
    const RenderOptions& opt_;
    physics::Radiometry radiometry_;
    bool sun_up_;
    Eigen::Vector3d to_sun_;
    double separation_m_;
    double cell_rad_;
    double power_k_;
    double inv_resolution_;
    std::vector<double> brdf_constant_;      // by material index: ρ_d/π (+ retro gain), or −1
    std::vector<double> diffuse_brdf_;       // by material index: ρ_d/π (the sunlit background)
    std::vector<PointFields> point_fields_;  // by material index
    std::vector<std::uint8_t> continues_;    // by material index: transmits or mirrors
    std::uint32_t volume_fields_ = 0;        // point_fields_ of an echo from the atmosphere
    std::int64_t volume_first_ = 0;          // first sample of volume_pe_
    std::vector<double> volume_pe_;          // expected backscatter photo-electrons per sample
    bool continues_any_ = false;
    // The linear-mode detector, when the sensor has one (docs/time-resolved.md §7).
    std::optional<physics::LinearDetector> linear_;
    std::optional<physics::WaveformSynth> synth_;
    std::optional<GeigerGate> geiger_;   // the Geiger-mode detector, when the sensor has one
    std::unique_ptr<CarryChain> chain_;  // a free-running one's, between render()'s chunks
    // An array's pixel-pulses: each pixel's share of the laser's energy (empty: no array).
    std::span<const float> share_;
    double sigma_p_ns_ = 0;       // the pulse's RMS width
    double merge_window_ps_ = 0;  // arrivals closer merge (merge_close_arrivals)
    bool matched_ = false;        // a measured pulse: echoes timed by the matched filter
    // Constant-fraction timing: the emitted pulse's own delay from its leading edge at the
    // fraction to its centroid, added to every edge so a lone echo is timed as its peak.
    double cfd_offset_ns_ = 0;
    double speckle_m_ = 0;  // speckle cells M, 0: none
    // Adaptive footprints: which sub-rays are probes and which not (both empty: sampled), the
    // footprint's mean square offset tangent per axis and its largest offset tangent squared.
    std::vector<std::uint32_t> probe_at_, rest_at_;  // the probes' sub-ray indices, the others'
    double m2_ = 0, max_offset2_ = 0;
    // Diffuse bounces per path (receiver.diffuse_bounces) and cos of the receiver's half IFOV.
    int bounces_ = 0;
    double fov_cos_ = 1.0, fov_half_rad_ = 0.5 * std::numbers::pi;
    // The image's wander may move the pixel's field of view off part of the spot: turbulence on,
    // and the field of view holds the whole footprint without it (else the pixel's share of the
    // spot, eq. 4′, already stands for the cut).
    bool image_cut_ = false;
    // Ω_spot / min(Ω_pix, Ω_spot): power_k_ holds the pixel's share of the spot (eq. 4′), which a
    // point seen inside the field of view (a bounce's next event) does not take.
    double nee_scale_ = 1.0;
};

}  // namespace mirage::render
