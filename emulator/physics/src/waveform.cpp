// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/waveform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "mirage/core/error.hpp"

namespace mirage::physics {

namespace {

// A cluster's photo-electrons and raw moments of its delays about its first one, and the hit of
// its strongest arrival. The cluster spans under a pulse width, so the raw moments lose nothing
// that matters to cancellation.
struct Cluster {
    std::int64_t start = 0;
    double pe = 0, s1 = 0, s2 = 0, s3 = 0;
    float best = -1;
    std::uint32_t hit = 0;

    void add(const Arrival& a) {
        const double w = a.pe, d = double(a.delay_ps - start), wd = w * d;
        pe += w;
        s1 += wd;
        s2 += wd * d;
        s3 += wd * d * d;
        if (a.pe > best) {
            best = a.pe;
            hit = a.hit;
        }
    }

    // The cluster as one arrival (narrower than 1 ps: delays are whole ps) or its two-point
    // quadrature, into out; returns how many.
    std::size_t quadrature(Arrival* out) const {
        if (!(pe > 0.0)) {  // nothing arrives: one empty arrival, not a division by 0
            out[0] = {start, 0.0f, hit};
            return 1;
        }
        const double inv = 1.0 / pe, mean = s1 * inv, m2 = s2 * inv;
        const double var = m2 - mean * mean;
        if (!(var >= 1.0)) {
            out[0] = {start + std::llround(mean), static_cast<float>(pe), hit};
            return 1;
        }
        const double mu3 = s3 * inv - mean * (3.0 * m2 - 2.0 * mean * mean);
        // Nodes x± about the mean: x₋ + x₊ = μ₃/σ², x₋·x₊ = −σ²; weights keep the mean.
        const double half = 0.5 * mu3 / var, root = std::sqrt(half * half + var);
        const double p_hi = (root - half) / (2.0 * root);
        out[0] = {start + std::llround(mean + half - root), static_cast<float>(pe * (1.0 - p_hi)),
                  hit};
        out[1] = {start + std::llround(mean + half + root), static_cast<float>(pe * p_hi), hit};
        return 2;
    }
};

#if defined(__AVX512F__)
// n ≤ 24 arrivals by rank: keys 32·delay + index are distinct and ordered as the stable order,
// and each arrival's place is the count of keys below its own, three vector compares (a
// comparison sort of a pulse's ~19 arrivals mispredicts most of its branches).
void sort_by_rank(std::vector<Arrival>& arrivals, std::vector<Arrival>& tmp) {
    const std::size_t n = arrivals.size();
    alignas(64) std::int64_t key[24];
    for (std::size_t i = 0; i < 24; ++i)
        key[i] = i < n ? arrivals[i].delay_ps * 32 + std::int64_t(i)
                       : std::numeric_limits<std::int64_t>::max();
    const __m512i k0 = _mm512_load_si512(key), k1 = _mm512_load_si512(key + 8),
                  k2 = _mm512_load_si512(key + 16);
    tmp.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const __m512i b = _mm512_set1_epi64(key[i]);
        const unsigned below = _mm_popcnt_u32(_mm512_cmplt_epi64_mask(k0, b)) +
                               _mm_popcnt_u32(_mm512_cmplt_epi64_mask(k1, b)) +
                               _mm_popcnt_u32(_mm512_cmplt_epi64_mask(k2, b));
        tmp[below] = arrivals[i];
    }
    arrivals.swap(tmp);
}
#endif

}  // namespace

// Keys 32·delay + index need delays in [0, 2⁵⁸); a pulse's are far inside. Otherwise, and without
// AVX-512, a stable insertion sort (the same order).
void sort_by_delay(std::vector<Arrival>& arrivals, std::vector<Arrival>& tmp) {
    const std::size_t n = arrivals.size();
    if (n < 2) return;
#if defined(__AVX512F__)
    constexpr std::int64_t kMaxDelay = std::int64_t{1} << 58;
    if (n <= 24 && std::all_of(arrivals.begin(), arrivals.end(), [](const Arrival& a) {
            return a.delay_ps >= 0 && a.delay_ps < kMaxDelay;
        })) {
        sort_by_rank(arrivals, tmp);
        return;
    }
#else
    (void)tmp;
#endif
    if (n > 32) {
        std::stable_sort(arrivals.begin(), arrivals.end(), [](const Arrival& a, const Arrival& b) {
            return a.delay_ps < b.delay_ps;
        });
        return;
    }
    for (std::size_t i = 1; i < n; ++i) {
        const Arrival a = arrivals[i];
        std::size_t j = i;
        for (; j > 0 && arrivals[j - 1].delay_ps > a.delay_ps; --j) arrivals[j] = arrivals[j - 1];
        arrivals[j] = a;
    }
}

// Gauss quadrature's nodes lie inside the cluster's span, and the next cluster starts past it,
// so the order holds. A cluster of n ≥ 2 writes at most two, at or before its own place.
void merge_arrivals(std::vector<Arrival>& arrivals, double window_ps) {
    std::size_t out = 0;
    for (std::size_t a = 0; a < arrivals.size();) {
        Cluster c{arrivals[a].delay_ps};
        c.add(arrivals[a]);
        std::size_t b = a + 1;
        for (; b < arrivals.size() && double(arrivals[b].delay_ps - c.start) < window_ps; ++b)
            c.add(arrivals[b]);
        if (b == a + 1) {
            arrivals[out++] = arrivals[a];
        } else {
            Arrival two[2];
            const std::size_t k = c.quadrature(two);
            for (std::size_t j = 0; j < k; ++j) arrivals[out++] = two[j];
        }
        a = b;
    }
    arrivals.resize(out);
}

WaveformSynth::WaveformSynth(const sensor::PulseShape& shape, double sample_period_ns,
                             const std::string& source) {
    if (!(sample_period_ns > 0 && sample_period_ns <= 1e3))
        throw ConfigError(source + ": the sample period " + std::to_string(sample_period_ns) +
                          " ns must be in (0, 1000] ns");
    period_ps_ = sample_period_ns * 1e3;
    trim(shape);
    begin_ps_ = static_cast<std::int64_t>(std::ceil(begin_ns_ * 1e3));
    end_ps_ = static_cast<std::int64_t>(std::ceil(end_ns_ * 1e3));
    step_ns_ = period_ns() / kSubSteps;
    // Row p holds s at begin + (p + kSubSteps·i)·step: the samples an arrival at phase p meets,
    // contiguous. Row kSubSteps is row 0 one sample on, for the interpolation at the last phase.
    const auto m = static_cast<std::size_t>(std::ceil((end_ns_ - begin_ns_) / step_ns_)) + 1;
    row_ = m / kSubSteps + 2;
    table_.assign((kSubSteps + 1) * row_, 0.0);
    for (std::size_t p = 0; p <= kSubSteps; ++p)
        for (std::size_t i = 0; i < row_; ++i) {
            const std::size_t k = p + kSubSteps * i;
            if (k < m) table_[p * row_ + i] = shape(begin_ns_ + double(k) * step_ns_) * period_ns();
        }
}

// The support, without tails below kTail of the peak: a Gaussian's ±8σ becomes ±4.8σ, dropping
// 1.6·10⁻⁶ of its area (samples that would each add less than 10⁻⁵ of the peak).
void WaveformSynth::trim(const sensor::PulseShape& shape) {
    constexpr double kTail = 1e-5;
    constexpr int kProbe = 4096;
    const double b = shape.begin_ns(), e = shape.end_ns(), h = (e - b) / kProbe;
    double peak = 0;
    for (int i = 0; i <= kProbe; ++i) peak = std::max(peak, shape(b + i * h));
    int first = 0, last = kProbe;
    while (first < kProbe && shape(b + first * h) < kTail * peak) ++first;
    while (last > first && shape(b + last * h) < kTail * peak) --last;
    begin_ns_ = b + std::max(0, first - 1) * h;
    end_ns_ = b + std::min(kProbe, last + 1) * h;
}

// From one sample to the next the position in the shape moves by exactly kSubSteps steps, so an
// arrival reads one row of the table at a fixed phase, and interpolates with the next row by a
// fixed weight: a contiguous loop that vectorises.
void WaveformSynth::add(const Arrival& a, std::int64_t j0, std::span<double> out) const {
    const std::int64_t lo = std::max(first_sample(a.delay_ps), j0);
    const std::int64_t hi =
        std::min(end_sample(a.delay_ps), j0 + static_cast<std::int64_t>(out.size()));
    if (lo >= hi) return;
    // Position in the shape of t_lo − t_a (≥ 0 but for rounding).
    const double u = 1e-3 * (double(lo) * period_ps_ - double(a.delay_ps));
    const double v = std::max(0.0, (u - begin_ns_) / step_ns_);
    const auto m = static_cast<std::size_t>(v);
    const double f = v - static_cast<double>(m), pe = a.pe;
    const std::size_t p = m % kSubSteps, i0 = m / kSubSteps;
    if (i0 >= row_) return;
    const std::size_t n = std::min(static_cast<std::size_t>(hi - lo), row_ - i0);
    const double* __restrict s0 = table_.data() + p * row_ + i0;
    const double* __restrict s1 = s0 + row_;
    double* __restrict o = out.data() + (lo - j0);
    accumulate(s0, s1, f, pe, o, n);
}

// o[k] += pe·(s0[k] + f·(s1[k] − s0[k])) for k < n. An arrival spans a few tens of samples: with
// AVX-512 the last partial vector is masked rather than left to scalar remainder loops, with the
// same operations (one subtraction, two fused multiply-adds) as the plain loop, so the same sums.
void WaveformSynth::accumulate(const double* __restrict s0, const double* __restrict s1, double f,
                               double pe, double* __restrict o, std::size_t n) {
#if defined(__AVX512F__)
    const __m512d vf = _mm512_set1_pd(f), vpe = _mm512_set1_pd(pe);
    for (std::size_t k = 0; k < n; k += 8) {
        const std::size_t left = n - k;
        const auto m = static_cast<__mmask8>(left >= 8 ? 0xFF : (1u << left) - 1u);
        const __m512d a = _mm512_maskz_loadu_pd(m, s0 + k), b = _mm512_maskz_loadu_pd(m, s1 + k);
        const __m512d y = _mm512_fmadd_pd(_mm512_sub_pd(b, a), vf, a);
        _mm512_mask_storeu_pd(o + k, m, _mm512_fmadd_pd(y, vpe, _mm512_maskz_loadu_pd(m, o + k)));
    }
#else
    for (std::size_t k = 0; k < n; ++k) o[k] += pe * (s0[k] + f * (s1[k] - s0[k]));
#endif
}

}  // namespace mirage::physics
