// SPDX-License-Identifier: Apache-2.0
// The Geiger-mode detector in the pipeline (docs/photon-counting.md §2, §4): per pulse (an
// array's pixel-pulse), the arrivals spread over the gate's bins by the pulse's shape, plus
// background and dark counts, make the pixel's event rate; its photon events, drawn from the
// pulse's stream 8, become points along the pixel's line of sight.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mirage/core/error.hpp"
#include "mirage/core/log_poly.hpp"
#include "mirage/core/rng.hpp"
#include "mirage/sensor/pulse_shape.hpp"
#include "shading.hpp"

namespace mirage::render {
namespace {

constexpr double kNsPerMeterTwoWay = 2e9 / physics::kSpeedOfLightMPerS;
constexpr std::uint32_t kCdfCells = 4096;
constexpr std::size_t kBinOffsets = 256;
constexpr std::uint32_t kNoRng = 0xFFFFFFFFu;  // a pixel without a stream yet; no neighbour
constexpr double kNoEventNs = std::numeric_limits<double>::infinity();  // b.first: no event

}  // namespace

// The gate (receiver's ranges), the pixel's effects and the pulse's share per bin.
void PulseShader::init_geiger() {
    if (sensor_.detector != sensor::DetectorKind::Geiger) return;
    const auto& p = sensor_.geiger;
    const auto& rx = sensor_.receiver;
    const std::string source = "sensor '" + sensor_.name + "'";
    GeigerGate g;
    g.open_ns = rx.min_range_m * kNsPerMeterTwoWay;
    g.bin_ns = p.bin_ns;
    const double bins = std::ceil((rx.max_range_m - rx.min_range_m) * kNsPerMeterTwoWay / p.bin_ns);
    if (!(bins >= 1.0 && bins < 4e9))
        throw ConfigError(source + ": detector.bin_ns: " + std::to_string(p.bin_ns) +
                          " ns cuts the range gate into too many bins");
    g.bins = static_cast<std::size_t>(bins);
    g.report_ns = std::numeric_limits<double>::infinity();
    if (p.free_running) {  // to the bin: the next window opens one period on
        if (!sensor_.array.on())
            throw ConfigError(source + ": detector.free_running: only for an array");
        g.free_running = true;
        g.period_ns = 1e9 * double(sensor_.scan->group_size()) / sensor_.scan->pulse_rate_hz();
        g.report_ns = double(g.bins) * g.bin_ns;
        const double period_bins = std::floor(g.period_ns / g.bin_ns);
        if (!(period_bins < 4e9))
            throw ConfigError(source + ": detector.bin_ns: " + std::to_string(p.bin_ns) +
                              " ns cuts the pulse period into too many bins");
        g.bins = std::max(g.bins, static_cast<std::size_t>(period_bins));
        chain_ = std::make_unique<CarryChain>();
    }
    g.pixel = {{p.dead_time_ns, p.paralyzable},
               p.jitter_ns,
               p.afterpulse_probability,
               p.afterpulse_delay_ns};
    g.dark_per_ns = p.dark_count_rate_hz * 1e-9;
    const auto& b = sensor_.beam;
    const auto shape = b.pulse_t_ns.empty()
                           ? sensor::PulseShape::gaussian(b.pulse_width_s * 1e9, source)
                           : sensor::PulseShape::tabulated(b.pulse_t_ns, b.pulse_power, source);
    // A Gaussian's tails beyond ±4.5σ hold 7e-6 of it: far below any bin's Poisson noise.
    g.shape_lo = b.pulse_t_ns.empty() ? -4.5 * shape.sigma_ns() : shape.begin_ns();
    const double hi = b.pulse_t_ns.empty() ? 4.5 * shape.sigma_ns() : shape.end_ns();
    tabulate_bin_weights(shape, hi, g);
    geiger_ = std::move(g);
}

// The pulse's share in each bin it reaches, per offset of its support's start inside its first
// bin (kBinOffsets steps: an arrival's time is taken to 1/kBinOffsets of a bin, 1 ps at 0.25 ns),
// so an arrival costs one table row. From the cumulative shape by midpoint sums (8 per cell),
// normalised to end at 1, linear between its points.
void PulseShader::tabulate_bin_weights(const sensor::PulseShape& shape, double hi,
                                       GeigerGate& g) const {
    const double lo = g.shape_lo, cell = (hi - lo) / kCdfCells;
    std::vector<double> cdf(kCdfCells + 1, 0.0);
    for (std::uint32_t c = 0; c < kCdfCells; ++c) {
        double s = 0;
        for (int m = 0; m < 8; ++m) s += shape(lo + (c + (m + 0.5) / 8.0) * cell);
        cdf[c + 1] = cdf[c] + s * cell / 8.0;
    }
    for (double& v : cdf) v /= cdf.back();
    const double inv_cell = 1.0 / cell;
    const auto cumulative = [&](double t_ns) {  // ∫ s over (−∞, t]
        const double x = (t_ns - lo) * inv_cell;
        if (!(x > 0.0)) return 0.0;
        if (x >= double(kCdfCells)) return 1.0;
        const auto c = static_cast<std::size_t>(x);
        return cdf[c] + (x - double(c)) * (cdf[c + 1] - cdf[c]);
    };
    g.span = static_cast<std::size_t>(std::ceil((hi - lo) / g.bin_ns)) + 1;
    g.weights.assign((kBinOffsets + 1) * g.span, 0.0);
    for (std::size_t f = 0; f <= kBinOffsets; ++f) {
        // The support starts f/kBinOffsets of a bin into bin 0: bin j spans (j − φ)·Δ to
        // (j + 1 − φ)·Δ after it.
        const double phi = double(f) / double(kBinOffsets);
        for (std::size_t j = 0; j < g.span; ++j)
            g.weights[f * g.span + j] = cumulative(lo + (double(j) + 1.0 - phi) * g.bin_ns) -
                                        cumulative(lo + (double(j) - phi) * g.bin_ns);
    }
    g.shares.resize(g.weights.size());
    for (std::size_t f = 0; f <= kBinOffsets; ++f) {
        double sum = 0;
        for (std::size_t j = 0; j < g.span; ++j)
            g.shares[f * g.span + j] = sum += std::max(0.0, g.weights[f * g.span + j]);
    }
}

// Where an arrival's photo-electrons fall: the gate's bin k0 takes the first entry of its table
// row w (span entries: the pulse's share per bin at the arrival's offset within its first bin).
PulseShader::ArrivalRow PulseShader::arrival_row(const physics::Arrival& a) const {
    const GeigerGate& g = *geiger_;
    const double d = double(a.delay_ps) * 1e-3 - g.open_ns;  // from the gate's opening
    const double x = (d + g.shape_lo) / g.bin_ns;            // the support's start, in bins
    const double k0 = std::floor(x);
    const auto f = static_cast<std::size_t>(std::lround((x - k0) * double(kBinOffsets)));
    // (an arrival is inside the receiver's ranges, so k0 is within a span of the gate)
    return {static_cast<std::int64_t>(k0), g.weights.data() + f * g.span};
}

// The pixel's event rate over the gate from its arrivals (sorted by delay): built in place while
// each arrival's bins follow the previous one's; arrivals closer than the pulse overlap, and their
// bins are merged first (sorted by bin, each bin's contributions summed in arrival order).
void PulseShader::event_rate(std::span<const physics::Arrival> arrivals, double noise_per_bin,
                             ShadeScratch& scratch) const {
    const GeigerGate& g = *geiger_;
    physics::EventRate& rate = scratch.rate;
    rate.begin(g.bins, noise_per_bin, g.bin_ns);
    bool overlap = false;
    for (const physics::Arrival& a : arrivals) {
        const ArrivalRow r = arrival_row(a);
        if (r.k0 + std::int64_t(g.span) > 0 && std::max<std::int64_t>(r.k0, 0) <= rate.last_key()) {
            overlap = true;
            break;
        }
        rate.add_run(r.k0, double(a.pe), r.w, g.span);
    }
    if (overlap) {
        auto& out = scratch.signal_bins;
        out.clear();
        for (const physics::Arrival& a : arrivals) {
            const ArrivalRow r = arrival_row(a);
            for (std::size_t j = 0; j < g.span; ++j) {
                const std::int64_t k = r.k0 + std::int64_t(j);
                const double s = double(a.pe) * r.w[j];
                if (k >= 0 && k < std::int64_t(g.bins) && s > 0.0)
                    out.push_back({static_cast<std::uint32_t>(k), s});
            }
        }
        std::stable_sort(out.begin(), out.end(),
                         [](const auto& x, const auto& y) { return x.k < y.k; });
        rate.begin(g.bins, noise_per_bin, g.bin_ns);
        for (const physics::SignalBin& b : out) rate.add(b.k, b.signal);
    }
    rate.finish();
}

// Background photo-electrons per ns at the pixel (the strongest arrival's surface under the sun)
// plus its dark counts; none with noise off.
double PulseShader::geiger_noise_per_ns(const std::vector<Hit>& hits,
                                        std::span<const physics::Arrival> arrivals) const {
    return opt_.noise ? geiger_->dark_per_ns + background_per_ns(hits, arrivals) : 0.0;
}

// Each pulse's events (with an array's crosstalk, frame by frame), then as pending returns
// (event j of a pulse: return j), with their kinds.
void PulseShader::geiger_returns(const RayBatch& g, const std::vector<Hit>& hits,
                                 const double* terms, const std::vector<double>& weighted_k,
                                 ShadeScratch& scratch, ShadedPoints& out) const {
    const std::size_t n = g.specs.size();
    GeigerBatch& b = scratch.geiger;
    b.events.clear();
    b.arrivals.clear();
    b.event_at.assign(1, 0);
    b.arrival_at.assign(1, 0);
    b.expected.clear();
    take_carry(b);
    first_levels(g.first, static_cast<std::uint32_t>(n), b);
    const bool crosstalk_on = sensor_.geiger.crosstalk_probability > 0.0 && opt_.noise;
    const bool single = sensor_.geiger.max_events == 1;  // one event a pixel: b.first
    if (single) b.first.resize(n);
    if (crosstalk_on && !single) {
        b.after.clear();
        b.after_at.assign(1, 0);
    }
    // A free-running array draws frame by frame, each pixel armed from the dead time its previous
    // frame carries (geiger_carry.cpp); a gated one draws the batch, then its crosstalk.
    const std::uint32_t pixels = std::max<std::uint32_t>(1, sensor_.array.pixels());
    const auto batch = static_cast<std::uint32_t>(n);
    for (std::uint32_t i0 = 0; i0 < batch;) {
        const std::uint32_t end =
            geiger_->free_running
                ? std::min(batch, i0 + pixels - std::uint32_t((g.first + i0) % pixels))
                : batch;
        b.own_end.clear();
        for (std::uint32_t i = i0; i < end; ++i) {
            out.stats.pulses++;
            const bool close =
                pixel_events(g, hits, terms, weighted_k, i, carried(g.first + i, b), scratch);
            if (single ? !(b.first[i].t_ns < kNoEventNs) : b.event_at[i + 1] == b.event_at[i])
                (close ? out.stats.too_close : out.stats.misses)++;
        }
        // Crosstalk frame by frame (the pixel-pulses of one laser pulse are adjacent).
        if (crosstalk_on)
            for (std::uint32_t i = i0; i < end; i += pixels) crosstalk(g, i, b);
        // (crosstalk() draws a whole frame only: one the batch cut it leaves as it is)
        if (geiger_->free_running)
            carry_on(g.first, i0, end,
                     crosstalk_on && (g.first + i0) % pixels == 0 && end - i0 == pixels, b);
        i0 = end;
    }
    if (crosstalk_on && !single) {
        std::swap(b.events, b.after);
        std::swap(b.event_at, b.after_at);
    }
    scratch.event_kind.clear();
    scratch.expected_pe.clear();
    for (std::uint32_t i = 0; i < n && single; ++i) {
        if (!(b.first[i].t_ns < kNoEventNs)) continue;
        add_event(i, 0, b.first[i], b.arrivals_of(i), scratch);
        scratch.expected_pe.push_back(b.expected[i]);
    }
    for (std::uint32_t i = 0; i < n && !single; ++i) {
        const std::span<const physics::Arrival> arrivals = b.arrivals_of(i);
        for (std::size_t e = b.event_at[i]; e < b.event_at[i + 1]; ++e)
            add_event(i, static_cast<std::uint32_t>(e - b.event_at[i]), b.events[e], arrivals,
                      scratch);
        scratch.expected_pe.insert(scratch.expected_pe.end(), b.event_at[i + 1] - b.event_at[i],
                                   b.expected[i]);
    }
}

// Pulse i's arrivals (sorted, times its energy factor) and events appended to the batch's, the
// pixel armed from `armed_from` ns into its gate; true if a hit was closer than the receiver's
// minimum range.
bool PulseShader::pixel_events(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                               const std::vector<double>& weighted_k, std::uint32_t i,
                               double armed_from, ShadeScratch& scratch) const {
    const GeigerGate& gate = *geiger_;
    GeigerBatch& b = scratch.geiger;
    auto& arrivals = scratch.arrivals;
    const std::uint64_t pulse = g.first + i;
    const bool close = pulse_arrivals(g, hits, terms, weighted_k, i, arrivals,
                                      scratch.paths ? &scratch.path : nullptr);
    physics::sort_by_delay(arrivals, scratch.sorted);
    const double energy = energy_factor(pulse);
    double expected = 0;
    for (auto& a : arrivals) expected += a.pe = static_cast<float>(a.pe * energy);
    const double noise_per_bin = geiger_noise_per_ns(hits, arrivals) * gate.bin_ns;
    // With noise off the photon statistics stay (they are the measurement); the pixel's own
    // noise (dark counts, background, jitter, afterpulses) goes.
    physics::GeigerPixel pixel = gate.pixel;
    if (!opt_.noise) pixel.jitter_ns = pixel.afterpulse_p = 0.0;
    const std::array<std::uint32_t, 4> block0 = {b.first_words[0][i], b.first_words[1][i],
                                                 b.first_words[2][i], b.first_words[3][i]};
    core::PulseRng rng(opt_.seed, pulse, kGeigerStream, block0, 1);
    const double level = b.level[i];
    // The gate's expected events are at most its noise and all the arrivals' photo-electrons (a
    // pulse's shares sum to 1 where the gate takes all of them): a first event above them is
    // none, and the rate need not be built. The margin covers the rate's rounding.
    if (level > (noise_per_bin * double(gate.bins) + expected) * (1.0 + 1e-9)) {
        scratch.events.clear();
        if (gate.free_running) b.own_end.push_back(armed_from);
    } else if (!first_event(arrivals, noise_per_bin, level, pixel, block0, scratch)) {
        event_rate(arrivals, noise_per_bin, scratch);
        draw_events(level, armed_from, pixel, rng, scratch);
    }
    if (sensor_.geiger.max_events == 1)
        b.first[i] =
            scratch.events.empty() ? physics::GeigerEvent{kNoEventNs} : scratch.events.front();
    else
        b.events.insert(b.events.end(), scratch.events.begin(), scratch.events.end());
    if (!scratch.events.empty())  // (read for its events' surfaces only)
        b.arrivals.insert(b.arrivals.end(), arrivals.begin(), arrivals.end());
    b.event_at.push_back(b.events.size());
    b.arrival_at.push_back(b.arrivals.size());
    b.expected.push_back(expected);
    return close;
}

// Block 0 of stream `stream` of the pulses [first, first + n) at once, word k into words[k].
void PulseShader::first_blocks(std::uint64_t first, std::uint32_t n, std::uint32_t stream,
                               GeigerBatch& b,
                               std::array<std::vector<std::uint32_t>, 4>& words) const {
    b.pulses.resize(n);
    b.blocks.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) b.pulses[i] = first + i;
    for (auto& w : words) w.resize(n);
    core::philox_blocks(opt_.seed, stream, b.pulses.data(), b.blocks.data(), n,
                        {words[0].data(), words[1].data(), words[2].data(), words[3].data()});
}

// The batch's pixel-pulses' first uniforms (block 0 of stream 8) at once, and from the first of
// each its first event's level −ln u (physics::first_level's draw).
void PulseShader::first_levels(std::uint64_t first, std::uint32_t n, GeigerBatch& b) const {
    first_blocks(first, n, kGeigerStream, b, b.first_words);
    b.level.resize(n);
    for (std::uint32_t i = 0; i < n; ++i)
        b.level[i] = -core::log_poly(core::uniform_of_word(b.first_words[0][i]));
}

// A gated pixel that reports its first event only: that event straight from its arrivals'
// rows (physics::gated_first_event), its signal uniform and jitter the next words of block 0 as
// draw_events would take them; false where the rate must be built (overlapping arrivals,
// rounding at a bin's edge) or the pixel is not such a one.
bool PulseShader::first_event(std::span<const physics::Arrival> arrivals, double noise_per_bin,
                              double level, const physics::GeigerPixel& pixel,
                              const std::array<std::uint32_t, 4>& block0,
                              ShadeScratch& scratch) const {
    const GeigerGate& g = *geiger_;
    if (g.free_running || sensor_.geiger.max_events != 1) return false;
    auto& runs = scratch.geiger.runs;
    runs.clear();
    for (const physics::Arrival& a : arrivals) {
        const ArrivalRow r = arrival_row(a);
        runs.push_back({r.k0, double(a.pe), r.w, r.w - g.weights.data() + g.shares.data(), g.span});
    }
    physics::GeigerEvent e;
    const auto result = physics::gated_first_event(runs, g.bins, noise_per_bin, g.bin_ns, level,
                                                   core::uniform_of_word(block0[1]), e);
    if (result == physics::FirstEventResult::Undecided) return false;
    scratch.events.clear();
    if (result == physics::FirstEventResult::Event) {
        if (pixel.jitter_ns > 0.0)
            e.t_ns += pixel.jitter_ns * core::inverse_normal_cdf(core::uniform_of_word(block0[2]));
        scratch.events.push_back(e);
    }
    return true;
}

// The pixel's events from its rate; a free-running pixel's re-arming time into b.own_end.
void PulseShader::draw_events(double level, double armed_from, const physics::GeigerPixel& pixel,
                              core::PulseRng& rng, ShadeScratch& scratch) const {
    const auto max = std::size_t(sensor_.geiger.max_events);
    if (!geiger_->free_running) {
        physics::geiger_events(scratch.rate, pixel, rng, level, max, scratch.events);
        return;
    }
    const physics::GeigerWindow window{armed_from, geiger_->report_ns, max};
    scratch.geiger.own_end.push_back(
        physics::geiger_events(scratch.rate, pixel, rng, level, window, scratch.events));
}

// Crosstalk over the frame of pulses [i0, i0 + N), its events appended to b.after per pixel in
// time order (an array's pixels in order; docs/photon-counting.md §2): the frame's events in time
// order; one while its pixel is dead (after an earlier detection, its own or a neighbour's) is
// lost, one while armed is kept and fires each of the pixel's four neighbours with the crosstalk
// probability (uniforms from the firing pixel-pulse's stream 9, in the order of its detections
// and of its neighbours), at the same time. Exact for a pixel that reports its first event only;
// with more, an own event lost to a crosstalk's dead time is not redrawn.
void PulseShader::crosstalk(const RayBatch& g, std::uint32_t i0, GeigerBatch& b) const {
    const auto& a = sensor_.array;
    const std::uint32_t n = std::min<std::uint32_t>(a.pixels(), std::uint32_t(g.specs.size() - i0));
    if (sensor_.geiger.max_events == 1) {  // in place (a frame the batch cut: as it is)
        if (g.specs[i0].pixel == 0) crosstalk_first(g, i0, n, b);
        return;
    }
    if (g.specs[i0].pixel != 0) {  // a frame cut by the batch (never in render()): as it is
        for (std::uint32_t p = 0; p < n; ++p) {
            b.after.insert(b.after.end(), b.events.begin() + std::ptrdiff_t(b.event_at[i0 + p]),
                           b.events.begin() + std::ptrdiff_t(b.event_at[i0 + p + 1]));
            b.after_at.push_back(b.after.size());
        }
        return;
    }
    b.own.clear();
    for (std::uint32_t p = 0; p < n; ++p)
        for (std::size_t e = b.event_at[i0 + p]; e < b.event_at[i0 + p + 1]; ++e)
            b.own.push_back({b.events[e], p, std::uint32_t(b.own.size())});
    std::sort(b.own.begin(), b.own.end());
    b.made.clear();
    b.kept.clear();
    b.armed.assign(n, -std::numeric_limits<double>::infinity());
    if (geiger_->free_running)  // dead from the previous frame (ns into this window)
        for (std::uint32_t p = 0; p < n; ++p)
            if (const double d = carried(g.first + i0 + p, b); d > 0.0) b.armed[p] = d;
    b.count.assign(n, 0);
    b.rng_of.assign(n, kNoRng);
    b.rngs.clear();
    auto seq = static_cast<std::uint32_t>(b.own.size());
    const auto later = [](const FrameEvent& x, const FrameEvent& y) { return y < x; };
    for (std::size_t next = 0; next < b.own.size() || !b.made.empty();) {
        FrameEvent q;
        if (!b.made.empty() && (next == b.own.size() || b.made.front() < b.own[next])) {
            std::pop_heap(b.made.begin(), b.made.end(), later);
            q = b.made.back();
            b.made.pop_back();
        } else {
            q = b.own[next++];
        }
        if (q.e.t_ns < b.armed[q.p] || b.count[q.p] >= std::uint32_t(sensor_.geiger.max_events))
            continue;
        b.kept.push_back(q);
        b.count[q.p]++;
        b.armed[q.p] = q.e.t_ns + sensor_.geiger.dead_time_ns;
        for (const std::uint32_t to : crosstalk_hits(g.first + i0, q.p, n, b))
            if (to != kNoRng) {
                b.made.push_back({{q.e.t_ns, physics::EventKind::Crosstalk}, to, seq++});
                std::push_heap(b.made.begin(), b.made.end(), later);
            }
    }
    by_pixel(b);
}

// The frame's crosstalk when each pixel reports its first event only, in closed form
// (physics::crosstalk_first_events): the same events as crosstalk()'s pass in time order, with
// each pixel's neighbours drawn from block 0 of its stream 9 (the uniforms its first detection
// takes there), the frame's blocks at once.
void PulseShader::crosstalk_first(const RayBatch& g, std::uint32_t i0, std::uint32_t n,
                                  GeigerBatch& b) const {
    const std::uint64_t frame_pulse = g.first + i0;
    first_blocks(frame_pulse, n, kCrosstalkStream, b, b.words);
    b.fires.resize(n);
    b.armed.assign(n, -std::numeric_limits<double>::infinity());
    physics::crosstalk_fires(
        {b.words[0].data(), b.words[1].data(), b.words[2].data(), b.words[3].data()},
        sensor_.geiger.crosstalk_probability, sensor_.array.columns, n, b.fires.data());
    if (geiger_->free_running)
        for (std::uint32_t p = 0; p < n; ++p)
            if (const double d = carried(frame_pulse + p, b); d > 0.0) b.armed[p] = d;
    const std::span<physics::GeigerEvent> events(b.first.data() + i0, n);
    physics::crosstalk_first_events(events, b.armed, b.fires, sensor_.array.columns, b.firing);
    if (geiger_->free_running)  // (for carry_on)
        for (std::uint32_t p = 0; p < n; ++p)
            if (events[p].t_ns < kNoEventNs)
                b.armed[p] = events[p].t_ns + sensor_.geiger.dead_time_ns;
}

// The neighbours (left, right, up, down) that pixel p's detection fires, kNoRng for the others:
// one uniform each from the pixel-pulse's stream 9, opened at its first detection.
std::array<std::uint32_t, 4> PulseShader::crosstalk_hits(std::uint64_t frame_pulse, std::uint32_t p,
                                                         std::uint32_t n, GeigerBatch& b) const {
    const auto& a = sensor_.array;
    if (b.rng_of[p] == kNoRng) {
        b.rng_of[p] = static_cast<std::uint32_t>(b.rngs.size());
        b.rngs.emplace_back(opt_.seed, frame_pulse + p, kCrosstalkStream);
    }
    core::PulseRng& rng = b.rngs[b.rng_of[p]];
    const std::uint32_t col = p % a.columns, row = p / a.columns;
    const std::int64_t step[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    std::array<std::uint32_t, 4> to{};
    for (int s = 0; s < 4; ++s) {
        const bool hit = rng.uniform() < sensor_.geiger.crosstalk_probability;
        const std::int64_t c = std::int64_t(col) + step[s][0], r = std::int64_t(row) + step[s][1];
        const bool inside = c >= 0 && r >= 0 && c < std::int64_t(a.columns) &&
                            r < std::int64_t(a.rows) && std::uint64_t(r * a.columns + c) < n;
        to[s] = hit && inside ? static_cast<std::uint32_t>(r * a.columns + c) : kNoRng;
    }
    return to;
}

// The frame's kept events (in time order) appended to b.after pixel by pixel, each pixel's in
// time order (a counting sort: b.count holds each pixel's kept events).
void PulseShader::by_pixel(GeigerBatch& b) const {
    const std::size_t base = b.after.size();
    std::size_t at = base;
    for (std::uint32_t& c : b.count) {  // each pixel's count becomes its first slot
        const std::size_t k = c;
        c = static_cast<std::uint32_t>(at - base);
        at += k;
    }
    b.after.resize(at);
    for (const FrameEvent& q : b.kept) b.after[base + b.count[q.p]++] = q.e;
    for (const std::uint32_t end : b.count) b.after_at.push_back(base + end);
}

// An event as a pending return at c/2 of its time since emission; a signal event takes the
// surface of the arrival nearest in time, any other the atmosphere's (no surface).
void PulseShader::add_event(std::uint32_t i, std::uint32_t k, const physics::GeigerEvent& e,
                            std::span<const physics::Arrival> arrivals,
                            ShadeScratch& scratch) const {
    const double t_ns = geiger_->open_ns + e.t_ns;
    std::uint32_t hit = kVolumeHit;
    if (e.kind == physics::EventKind::Signal && !arrivals.empty()) {
        const auto at = static_cast<std::int64_t>(t_ns * 1e3);
        auto it = std::lower_bound(arrivals.begin(), arrivals.end(), at,
                                   [](const auto& a, std::int64_t v) { return a.delay_ps < v; });
        if (it == arrivals.end() ||
            (it != arrivals.begin() && at - std::prev(it)->delay_ps < it->delay_ps - at))
            --it;
        hit = it->hit;
    }
    scratch.pending.push_back({t_ns / kNsPerMeterTwoWay, 0.0, i, hit, k});
    scratch.event_kind.push_back(static_cast<std::uint8_t>(1 + static_cast<int>(e.kind)));
}

// Ranges and positions of the events along each pixel's line of sight, no intensity, no voids.
void PulseShader::event_points(const RayBatch& g, ShadeScratch& scratch) const {
    const std::size_t np = scratch.pending.size();
    scratch.range.resize(np);
    scratch.n_laser.assign(scratch.expected_pe.begin(), scratch.expected_pe.end());
    scratch.intensity.assign(np, 0);
    scratch.voids.assign(np, 0.0);
    for (int a = 0; a < 3; ++a) {
        scratch.dir[a].resize(np);
        scratch.at[a].resize(np);
    }
    for (std::size_t j = 0; j < np; ++j) {
        const std::uint32_t i = scratch.pending[j].i;
        const double r = scratch.pending[j].range_m;
        scratch.range[j] = r;
        for (int a = 0; a < 3; ++a) {
            scratch.dir[a][j] = g.direction[a][i];
            scratch.at[a][j] = g.origin[a][i] + r * g.direction[a][i];
        }
    }
}

}  // namespace mirage::render
