// SPDX-License-Identifier: Apache-2.0
// Coincidence processing (docs/photon-counting.md §5).
#include "mirage/render/coincidence.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <thread>

#include "mirage/core/error.hpp"
#include "mirage/render/trace_batches.hpp"
#include "ray_batch.hpp"

namespace mirage::render {
namespace {

// A gate must look down: its height falls along the line (cells are vertical columns).
constexpr double kMinDownward = 0.5;

// P(Poisson(mean) ≥ k) by the complement of the first k terms (k small where it matters).
double poisson_tail(double mean, std::uint32_t k) {
    if (k == 0) return 1.0;
    if (!(mean > 0.0)) return 0.0;
    double term = std::exp(-mean), below = term;
    for (std::uint32_t i = 1; i < k; ++i) {
        term *= mean / double(i);
        below += term;
        if (term < 1e-300 * below) break;
    }
    return std::max(0.0, 1.0 - below);
}

std::int64_t cell_key(std::int64_t ix, std::int64_t iy) { return (ix << 32) ^ (iy & 0xFFFFFFFFll); }

// An offset as a float (ColumnEvent's), in integer units of 2^-30 m (CoincidenceGrid::BinSum),
// still a double so that floor_gates() vectorises: exact for an offset of 8 mm or more, within
// 1e-9 m below; halves round to even, as the vector unit rounds.
inline double fixed_units(double offset) {
    return std::nearbyint(double(static_cast<float>(offset)) * 0x1p30);
}
std::int64_t fixed(float offset) { return static_cast<std::int64_t>(fixed_units(offset)); }

// A batch of gates' arithmetic over whole arrays: mid-gate x and y, floor(x / cell),
// floor(y / cell), the floors of the top's and the bottom's height over the bin, the event's bin
// (stop holding its height on entry) kept within them, and the event's offsets from the cell's
// corner and that bin's floor in fixed units (qx, qy holding its x and y on entry). GCC
// vectorises it with -fno-trapping-math (given restrict parameters; restrict locals or one array
// of rows it would not); the same IEEE operations as one gate at a time, so the same values.
void floor_gates(std::size_t n, const GateLines& l, double cell, double bin, double* __restrict mx,
                 double* __restrict my, double* __restrict cx, double* __restrict cy,
                 double* __restrict top, double* __restrict bottom, double* __restrict stop,
                 double* __restrict qx, double* __restrict qy, double* __restrict qz) {
    const double half = 0.5 * (l.r0 + l.r1), r0 = l.r0, r1 = l.r1;
    const double *ox = l.ox.data(), *oy = l.oy.data(), *oz = l.oz.data();
    const double *dx = l.dx.data(), *dy = l.dy.data(), *dz = l.dz.data();
    for (std::size_t i = 0; i < n; ++i) {
        mx[i] = ox[i] + half * dx[i];
        my[i] = oy[i] + half * dy[i];
        cx[i] = std::floor(mx[i] / cell);
        cy[i] = std::floor(my[i] / cell);
        top[i] = std::floor((oz[i] + r0 * dz[i]) / bin);
        bottom[i] = std::floor((oz[i] + r1 * dz[i]) / bin);
        const double ez = stop[i], s = std::floor(ez / bin);
        stop[i] = s < bottom[i] ? bottom[i] : s > top[i] ? top[i] : s;
        qx[i] = fixed_units(qx[i] - cx[i] * cell);  // (qx, qy in: the event's x and y)
        qy[i] = fixed_units(qy[i] - cy[i] * cell);
        qz[i] = fixed_units(ez - stop[i] * bin);
    }
}

// A cell key's first slot in a table of mask + 1 (a power of two): Fibonacci hashing, as the
// keys of neighbouring cells differ in their low bits of x and of y.
std::size_t slot_of(std::int64_t key, std::size_t mask) {
    return static_cast<std::size_t>((std::uint64_t(key) * 0x9E3779B97F4A7C15ull) >> 32) & mask;
}

// In a table of open addressing (a power of two in size, at most half full, linear probing): the
// slot `same` matches, else the empty one where `key` goes.
template <class Slot, class Empty, class Same>
Slot& probe(std::vector<Slot>& slots, std::int64_t key, Empty empty, Same same) {
    const std::size_t mask = slots.size() - 1;
    for (std::size_t at = slot_of(key, mask);; at = (at + 1) & mask)
        if (empty(slots[at]) || same(slots[at])) return slots[at];
}

// A batch's lines cover its gates.
void check_lines(const GateLines& l, std::size_t n) {
    for (const auto* line : {&l.ox, &l.oy, &l.oz, &l.dx, &l.dy, &l.dz})
        if (line->size() < n)
            throw Error("coincidence: lines for " + std::to_string(line->size()) + " of " +
                        std::to_string(n) + " gates");
}

// The gates of a batch that look up, or whose cell, bins or event offsets (floor_gates) are not
// finite or would not fit their integers (a NaN anywhere in a gate or its event ends up there).
// One pass that vectorises; the caller looks for which only when some are.
std::size_t unfit_gates(std::size_t n, const double* dz, const double* cx, const double* cy,
                        const double* top, const double* bottom, const double* stop,
                        const double* qx, const double* qy, const double* qz) {
    // Each test counted as 0 or 1 (no short circuit: no branch in the loop).
    const auto out = [](double v, double limit) { return int(!(std::fabs(v) < limit)); };
    std::size_t unfit = 0;
    for (std::size_t i = 0; i < n; ++i)
        unfit +=
            std::size_t(int(!(dz[i] < -kMinDownward)) | out(cx[i], 0x1p62) | out(cy[i], 0x1p62) |
                        out(top[i], 0x1p31) | out(bottom[i], 0x1p31) | out(stop[i], 0x1p31) |
                        out(qx[i], 0x1p62) | out(qy[i], 0x1p62) | out(qz[i], 0x1p62));
    return unfit;
}

std::size_t thread_count(int threads) {
    return threads > 0 ? std::size_t(threads)
                       : std::size_t(std::max(1u, std::thread::hardware_concurrency()));
}

// f(0) … f(parts − 1), each on a thread of its own (f(0) on the caller's); the first exception
// any of them threw is rethrown once all are done.
template <class F>
void run_parts(std::size_t parts, F&& f) {
    std::vector<std::exception_ptr> error(parts);
    const auto guarded = [&](std::size_t t) {
        try {
            f(t);
        } catch (...) {
            error[t] = std::current_exception();
        }
    };
    std::vector<std::thread> threads;
    for (std::size_t t = 1; t < parts; ++t) threads.emplace_back(guarded, t);
    guarded(0);
    for (auto& th : threads) th.join();
    for (const auto& e : error)
        if (e) std::rethrow_exception(e);
}

}  // namespace

namespace coincidence_detail {

// An event bin of a column's dwell: its events and the gates armed there.
struct Bin {
    std::int32_t b;
    std::uint32_t h, armed;
    std::uint32_t first, count;  // its sums in the scratch's list
};

// Whether values spanning `range` bins are cheaper counted over the range than sorted.
inline bool narrow(std::uint64_t range, std::size_t values) {
    return range <= 8 * std::uint64_t(values) + 256;
}

// How many of a column's values (its gates' top or bottom bins) are at least b, for many b: by
// counts over the values' range when it is narrow (a column's gates open and close within a
// few bins of each other), else by a sorted copy. O(values + range), or O(values log values).
class AtLeast {
  public:
    template <class Value>
    void build(std::size_t n, Value v) {
        n_ = n;
        if (n == 0) return;
        lo_ = hi_ = v(0);
        for (std::size_t i = 1; i < n; ++i) {
            const std::int32_t x = v(i);
            lo_ = std::min(lo_, x);
            hi_ = std::max(hi_, x);
        }
        const std::uint64_t range = std::uint64_t(std::int64_t(hi_) - lo_) + 1;
        dense_ = narrow(range, n);
        if (dense_) {
            counts_.assign(range + 1, 0);
            for (std::size_t i = 0; i < n; ++i) counts_[std::size_t(v(i) - lo_)]++;
            sum_down();
        } else {
            sorted_.resize(n);
            for (std::size_t i = 0; i < n; ++i) sorted_[i] = v(i);
            std::sort(sorted_.begin(), sorted_.end());
        }
    }
    // From counts by bin (counts[k]: values lo + k, both ends non-zero) or a list.
    void build(std::int32_t lo, std::span<const std::uint32_t> counts,
               std::span<const std::int32_t> values) {
        if (!values.empty() || counts.empty()) {
            build(values.size(), [&](std::size_t i) { return values[i]; });
            return;
        }
        lo_ = lo;
        hi_ = lo + static_cast<std::int32_t>(counts.size() - 1);
        dense_ = true;
        counts_.assign(counts.begin(), counts.end());
        counts_.push_back(0);
        sum_down();
    }
    std::size_t from(std::int64_t b) const {
        if (n_ == 0 || b > hi_) return 0;
        if (b <= lo_) return n_;
        if (dense_) return counts_[std::size_t(b - lo_)];
        return std::size_t(sorted_.end() - std::lower_bound(sorted_.begin(), sorted_.end(), b));
    }

  private:
    // counts_[k] from the count at lo_ + k to the count at or above it.
    void sum_down() {
        for (std::size_t k = counts_.size() - 1; k-- > 0;) counts_[k] += counts_[k + 1];
        n_ = counts_[0];
    }
    std::size_t n_ = 0;
    std::int32_t lo_ = 0, hi_ = 0;
    bool dense_ = true;
    std::vector<std::uint32_t> counts_;  // counts_[k]: values ≥ lo_ + k
    std::vector<std::int32_t> sorted_;
};

}  // namespace coincidence_detail

struct CoincidenceGrid::Scratch {
    coincidence_detail::AtLeast tops, bottoms;
    BinSums table;             // a dwell's events summed (keeping gates)
    std::vector<BinSum> sums;  // the dwell's, by bin (top first) and class
    std::vector<coincidence_detail::Bin> bins;
};

CoincidenceGrid::CoincidenceGrid(CoincidenceParams p) : p_(p) {
    if (!(p_.cell_m > 0.0) || !(p_.bin_m > 0.0) || !(p_.false_alarm > 0.0 && p_.false_alarm < 1.0))
        throw ConfigError(
            "coincidence: cell and bin sizes must be > 0 and the false-alarm "
            "probability in (0, 1)");
}

void CoincidenceGrid::add(const Gate& gate, const GateEvent* first) {
    const GateLines one{{&gate.origin.x(), 1},
                        {&gate.origin.y(), 1},
                        {&gate.origin.z(), 1},
                        {&gate.dir.x(), 1},
                        {&gate.dir.y(), 1},
                        {&gate.dir.z(), 1},
                        gate.r0,
                        gate.r1};
    add(one, {&first, 1});
}

void CoincidenceGrid::add(const GateLines& l, std::span<const GateEvent* const> first) {
    const std::size_t n = first.size();
    check_lines(l, n);
    Floors& f = floors_;
    for (auto* v : {&f.mx, &f.my, &f.cx, &f.cy, &f.top, &f.bottom, &f.stop, &f.qx, &f.qy, &f.qz})
        v->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const GateEvent* e = first[i];
        f.qx[i] = e ? e->x : 0.0, f.qy[i] = e ? e->y : 0.0, f.stop[i] = e ? e->z : 0.0;
    }
    floor_gates(n, l, p_.cell_m, p_.bin_m, f.mx.data(), f.my.data(), f.cx.data(), f.cy.data(),
                f.top.data(), f.bottom.data(), f.stop.data(), f.qx.data(), f.qy.data(),
                f.qz.data());
    if (unfit_gates(n, l.dz.data(), f.cx.data(), f.cy.data(), f.top.data(), f.bottom.data(),
                    f.stop.data(), f.qx.data(), f.qy.data(), f.qz.data()) > 0)
        refuse_batch(l, n);
    for (std::size_t i = 0; i < n; ++i) add_one(i, first[i]);
}

// Throws for the first gate unfit_gates() counted, before any of the batch is added.
void CoincidenceGrid::refuse_batch(const GateLines& l, std::size_t n) const {
    for (std::size_t i = 0; i < n; ++i)
        if (!(l.dz[i] < -kMinDownward))
            throw ConfigError("coincidence: a gate looks " + std::to_string(l.dz[i]) +
                              " down (needs a line of sight within 60° of nadir)");
    throw ConfigError("coincidence: a gate or its event is not finite, or too far out");
}

// Gate i of the batch in floors_ into its column.
void CoincidenceGrid::add_one(std::size_t i, const GateEvent* first) {
    const Floors& f = floors_;
    if (p_.window && !p_.window->contains(f.mx[i], f.my[i])) return;
    const auto ix = static_cast<std::int64_t>(f.cx[i]);
    const auto iy = static_cast<std::int64_t>(f.cy[i]);
    const std::int64_t key = cell_key(ix, iy);
    if (!last_.column || last_.key != key) {
        last_.key = key;
        last_.column = &column(ix, iy);
    }
    Column& c = *last_.column;
    const auto top = static_cast<std::int32_t>(f.top[i]);
    const auto bottom = static_cast<std::int32_t>(f.bottom[i]);
    const std::int32_t stop = first ? static_cast<std::int32_t>(f.stop[i]) : bottom;
    const std::uint32_t number = c.count++;
    if (first) {
        ++c.fired;
        if (keep_gates())  // offsets from the cell's corner and the bin's floor (ColumnEvent)
            c.events.push_back({number, stop, static_cast<float>(first->x - double(ix) * p_.cell_m),
                                static_cast<float>(first->y - double(iy) * p_.cell_m),
                                static_cast<float>(first->z - double(stop) * p_.bin_m),
                                first->classification, first->signal});
        else  // the same offsets as fixed() would make of them (floor_gates)
            c.sums.add({stop, first->classification, 1, first->signal ? 1u : 0u,
                        static_cast<std::int64_t>(f.qx[i]), static_cast<std::int64_t>(f.qy[i]),
                        static_cast<std::int64_t>(f.qz[i])});
    }
    if (keep_gates()) {
        c.gates.push_back({top, bottom, stop});
        return;
    }
    c.tops.add(top);
    c.bottoms.add(bottom);
    c.armed_bins += static_cast<std::uint64_t>(std::int64_t(top) - stop + 1);
}

CoincidenceGrid::Column& CoincidenceGrid::column(std::int64_t ix, std::int64_t iy) {
    const std::int64_t key = cell_key(ix, iy);
    const auto empty = [](const Slot& s) { return s.index == kEmpty; };
    if (2 * (columns_.size() + 1) > slots_.size()) {  // at most half full
        std::vector<Slot> old(std::max<std::size_t>(64, 2 * slots_.size()));
        old.swap(slots_);
        for (const Slot& sl : old)
            if (sl.index != kEmpty)
                probe(slots_, sl.key, empty, [](const Slot&) { return false; }) = sl;
    }
    Slot& sl = probe(slots_, key, empty, [&](const Slot& s) { return s.key == key; });
    if (sl.index != kEmpty) return columns_[sl.index];
    Column& c = columns_.emplace_back();  // before the slot names it (it may throw)
    sl = {key, static_cast<std::uint32_t>(columns_.size() - 1)};
    c.ix = ix;
    c.iy = iy;
    return c;
}

CoincidenceGrid::BinSum CoincidenceGrid::sum_of(const ColumnEvent& e) {
    return {e.bin, e.classification, 1, e.signal ? 1u : 0u, fixed(e.dx), fixed(e.dy), fixed(e.dz)};
}

void CoincidenceGrid::BinSums::add(const BinSum& e) {
    if (2 * (used + 1) > slots.size()) {  // at most half full
        std::vector<BinSum> old(std::max<std::size_t>(8, 2 * slots.size()));
        old.swap(slots);
        used = 0;
        for (const BinSum& o : old)
            if (o.events) add(o);
    }
    const auto key = (std::int64_t(std::uint32_t(e.bin)) << 8) | e.classification;
    BinSum& sl = probe(
        slots, key, [](const BinSum& s) { return s.events == 0; },
        [&](const BinSum& s) { return s.bin == e.bin && s.classification == e.classification; });
    if (sl.events == 0) {
        sl = e;
        ++used;
        return;
    }
    sl.events += e.events;
    sl.signal += e.signal;
    sl.x += e.x, sl.y += e.y, sl.z += e.z;
}

// A value outside the counted range (or any, once listed): widens the range or lists.
void CoincidenceGrid::Tally::add_outside(std::int32_t v) {
    if (!values.empty()) {
        values.push_back(v);
        return;
    }
    if (counts.empty()) {
        lo = v;
        counts.assign(1, 0);
    }
    const std::int64_t k = std::int64_t(v) - lo;
    const std::int64_t hi = std::max<std::int64_t>(k, std::int64_t(counts.size()) - 1);
    if (hi - std::min<std::int64_t>(k, 0) >= std::int64_t(kWide)) {
        list();
        values.push_back(v);
        return;
    }
    if (k < 0) {
        counts.insert(counts.begin(), static_cast<std::size_t>(-k), 0);
        lo = v;
    } else if (k >= std::int64_t(counts.size())) {
        counts.resize(static_cast<std::size_t>(k) + 1, 0);
    }
    counts[static_cast<std::size_t>(std::int64_t(v) - lo)]++;
}

// From counts to a list of the values (a wide range).
void CoincidenceGrid::Tally::list() {
    for (std::size_t k = 0; k < counts.size(); ++k)
        values.insert(values.end(), counts[k], lo + static_cast<std::int32_t>(k));
    counts.clear();
}

void CoincidenceGrid::Tally::merge(const Tally& other) {
    if (!other.values.empty()) {
        list();
        values.insert(values.end(), other.values.begin(), other.values.end());
        return;
    }
    for (std::size_t k = 0; k < other.counts.size(); ++k)
        for (std::uint32_t n = 0; n < other.counts[k]; ++n)
            add(other.lo + static_cast<std::int32_t>(k));
}

std::vector<CoincidencePoint> CoincidenceGrid::finish(CoincidenceStats* stats,
                                                      std::uint32_t gates_per_cell) const {
    const std::uint32_t dwell = gates_per_cell ? gates_per_cell : p_.gates_per_cell;
    if (dwell && !keep_gates())
        throw Error("coincidence: a dwell of " + std::to_string(dwell) +
                    " gates from a grid made without dwells");
    // Cells in key order, so neither the points' order nor the noise's sum depends on threads.
    std::vector<std::pair<std::int64_t, const Column*>> cells;
    cells.reserve(columns_.size());
    for (const Column& c : columns_) cells.emplace_back(cell_key(c.ix, c.iy), &c);
    std::sort(cells.begin(), cells.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t parts =
        std::min(thread_count(p_.threads), std::max<std::size_t>(1, cells.size() / 64));
    std::vector<std::vector<CoincidencePoint>> out(parts);
    std::vector<double> noise(cells.size(), 0.0);
    std::vector<std::uint64_t> gates(parts, 0), events(parts, 0);
    run_parts(parts, [&](std::size_t t) {
        Scratch scratch;
        for (std::size_t i = cells.size() * t / parts; i < cells.size() * (t + 1) / parts; ++i) {
            const Column& c = *cells[i].second;
            const std::size_t g = dwell ? std::min<std::size_t>(dwell, c.count) : c.count;
            const std::size_t m = events_of(c, g);
            finish_column({c, g, m}, scratch, out[t], noise[i]);
            gates[t] += g;
            events[t] += m;
        }
    });
    std::vector<CoincidencePoint> all;
    for (auto& part : out) all.insert(all.end(), part.begin(), part.end());
    if (stats) {
        double noise_sum = 0;
        for (const double v : noise) noise_sum += v;
        stats->gates = stats->events = 0;
        for (std::size_t t = 0; t < parts; ++t)
            stats->gates += gates[t], stats->events += events[t];
        stats->cells = cells.size();
        stats->points = all.size();
        stats->noise_per_bin = cells.empty() ? 0.0 : noise_sum / double(cells.size());
    }
    return all;
}

// Column c's events among its first g gates (without kept gates, g is all of them).
std::size_t CoincidenceGrid::events_of(const Column& c, std::size_t g) const {
    if (!keep_gates()) return c.fired;
    const auto before = [](const ColumnEvent& e, std::size_t n) { return e.gate < n; };
    return static_cast<std::size_t>(std::lower_bound(c.events.begin(), c.events.end(), g, before) -
                                    c.events.begin());
}

void CoincidenceGrid::append(CoincidenceGrid&& later) {
    last_.column = nullptr;
    for (Column& from : later.columns_) {
        Column& c = column(from.ix, from.iy);
        if (c.count == 0) {
            c = std::move(from);
            continue;
        }
        const std::uint32_t offset = c.count;
        c.count += from.count;
        c.gates.insert(c.gates.end(), from.gates.begin(), from.gates.end());
        c.tops.merge(from.tops);
        c.bottoms.merge(from.bottoms);
        c.armed_bins += from.armed_bins;
        c.fired += from.fired;
        for (const BinSum& e : from.sums.slots)
            if (e.events) c.sums.add(e);
        c.events.reserve(c.events.size() + from.events.size());
        for (ColumnEvent e : from.events) {
            e.gate += offset;
            c.events.push_back(e);
        }
    }
    later.columns_.clear();
    later.slots_.clear();
    later.last_.column = nullptr;
}

namespace {

using coincidence_detail::AtLeast;
using coincidence_detail::Bin;

// The distinct bins of a column's sums (by bin, top first), with their events and the gates armed
// there: gates covering b, less those that fired above it. (A template: the sums' type is
// CoincidenceGrid's own.)
template <class Sums>
void bins_of(const Sums& sums, const AtLeast& tops, const AtLeast& bottoms,
             std::vector<Bin>& bins) {
    bins.clear();
    std::size_t above = 0;
    for (std::size_t first = 0; first < sums.size();) {
        const std::int32_t b = sums[first].bin;
        std::size_t end = first;
        std::uint32_t h = 0;
        for (; end < sums.size() && sums[end].bin == b; ++end) h += sums[end].events;
        const auto covering = static_cast<std::ptrdiff_t>(tops.from(b)) -
                              static_cast<std::ptrdiff_t>(bottoms.from(std::int64_t(b) + 1));
        const auto armed = std::max<std::ptrdiff_t>(covering - std::ptrdiff_t(above), 0);
        bins.push_back({b, h, static_cast<std::uint32_t>(armed), static_cast<std::uint32_t>(first),
                        static_cast<std::uint32_t>(end - first)});
        above += h;
        first = end;
    }
}

}  // namespace

// The dwell's first events summed by bin and class into s.sums, bins top first and classes in
// order: a column's sums, or (keeping gates) its first m events summed the same way.
void CoincidenceGrid::sums_by_bin(const Dwell& d, Scratch& s) const {
    const BinSums* sums = &d.c.sums;
    if (keep_gates()) {
        s.table.slots.clear();
        s.table.used = 0;
        for (std::size_t j = 0; j < d.m; ++j) s.table.add(sum_of(d.c.events[j]));
        sums = &s.table;
    }
    s.sums.clear();
    for (const BinSum& e : sums->slots)
        if (e.events) s.sums.push_back(e);
    std::sort(s.sums.begin(), s.sums.end(), [](const BinSum& a, const BinSum& b) {
        return a.bin != b.bin ? a.bin > b.bin : a.classification < b.classification;
    });
}

// Per event bin b: n̂_b = −ln(1 − h_b/A_b) over its armed gates A_b. The noise per gate-bin is the
// column's events over its armed gate-bins, taken again without the bins that stand out (a
// surface's own events).
void CoincidenceGrid::finish_column(const Dwell& d, Scratch& s, std::vector<CoincidencePoint>& out,
                                    double& noise) const {
    if (d.m == 0) return;
    const Column& c = d.c;
    std::uint64_t armed_bins = c.armed_bins;
    if (keep_gates()) {
        for (std::size_t i = 0; i < d.g; ++i)
            armed_bins +=
                static_cast<std::uint64_t>(std::int64_t(c.gates[i].top) - c.gates[i].stop + 1);
        s.tops.build(d.g, [&](std::size_t i) { return c.gates[i].top; });
        s.bottoms.build(d.g, [&](std::size_t i) { return c.gates[i].bottom; });
    } else {
        s.tops.build(c.tops.lo, c.tops.counts, c.tops.values);
        s.bottoms.build(c.bottoms.lo, c.bottoms.counts, c.bottoms.values);
    }
    sums_by_bin(d, s);
    bins_of(s.sums, s.tops, s.bottoms, s.bins);
    const auto stands_out = [&](const Bin& x, double nu) {
        return x.h >= p_.min_events && poisson_tail(nu * x.armed, x.h) < p_.false_alarm;
    };
    noise = double(d.m) / double(std::max<std::uint64_t>(1, armed_bins));
    for (int pass = 0; pass < 3; ++pass) {  // a few rounds settle which bins stand out
        double h_rest = double(d.m), a_rest = double(armed_bins);
        for (const Bin& x : s.bins)
            if (stands_out(x, noise)) h_rest -= x.h, a_rest -= x.armed;
        noise = a_rest > 0.0 ? std::max(0.0, h_rest) / a_rest : 0.0;
    }
    for (const Bin& x : s.bins)
        if (stands_out(x, noise) && x.armed > 0)
            out.push_back(bin_point(c, x.b, x.armed, {s.sums.data() + x.first, x.count}));
}

// A standing-out bin's point from its sums (classes in order): its events' mean position, most
// frequent class (the lower of a tie) and truth share.
CoincidencePoint CoincidenceGrid::bin_point(const Column& c, std::int32_t b, std::uint32_t armed,
                                            std::span<const BinSum> sums) const {
    CoincidencePoint pt;
    std::uint32_t h = 0, signal = 0, most = 0;
    std::int64_t x = 0, y = 0, z = 0;
    for (const BinSum& e : sums) {
        h += e.events, signal += e.signal;
        x += e.x, y += e.y, z += e.z;
        if (e.events > most) most = e.events, pt.classification = e.classification;
    }
    pt.events = h;
    pt.gates = armed;
    pt.expected = h >= armed ? INFINITY : -std::log1p(-double(h) / double(armed));
    const double n = double(h);
    pt.x = double(c.ix) * p_.cell_m + double(x) * 0x1p-30 / n;
    pt.y = double(c.iy) * p_.cell_m + double(y) * 0x1p-30 / n;
    pt.z = double(b) * p_.bin_m + double(z) * 0x1p-30 / n;
    pt.signal_share = double(signal) / n;
    return pt;
}

void FirstEventSink::write(std::span<const core::PointRecord> points) {
    if (next_) next_->write(points);
    for (const auto& p : points)
        if (p.return_number == 1)
            events.push_back({p.pulse, {p.x, p.y, p.z, p.classification, p.event == 1}});
}

void FirstEventSink::pulses_done(std::uint64_t next_pulse) {
    if (next_) next_->pulses_done(next_pulse);
}

void FirstEventSink::finish() {
    if (next_) next_->finish();
}

namespace {

// Pulses [lo, hi) of the setup's run (lo a whole number of trace batches) as gates into `grid`.
void add_gates(const Setup& setup, std::span<const FirstEvent> events, std::uint64_t lo,
               std::uint64_t hi, CoincidenceGrid& grid) {
    const auto& rx = setup.sensor.receiver;
    const RayBatchBuilder builder(setup.sensor, setup.trajectory, setup.mount, setup.options.start);
    const std::size_t batch = trace_batch_pulses(setup.sensor);
    std::size_t next = static_cast<std::size_t>(
        std::lower_bound(events.begin(), events.end(), lo,
                         [](const FirstEvent& e, std::uint64_t p) { return e.pulse < p; }) -
        events.begin());
    RayBatch g;
    std::vector<const GateEvent*> fired;
    for (std::uint64_t first = lo; first < hi; first += batch) {
        builder.build_lines(
            first, static_cast<std::size_t>(std::min<std::uint64_t>(batch, hi - first)), g);
        fired.assign(g.specs.size(), nullptr);
        for (; next < events.size() && events[next].pulse < first + fired.size(); ++next)
            if (events[next].pulse >= first && !fired[events[next].pulse - first])
                fired[events[next].pulse - first] = &events[next].event;
        grid.add({g.origin[0], g.origin[1], g.origin[2], g.direction[0], g.direction[1],
                  g.direction[2], rx.min_range_m, rx.max_range_m},
                 fired);
    }
}

}  // namespace

CoincidenceGrid coincidence_grid(const Setup& setup, std::span<const FirstEvent> events,
                                 const CoincidenceParams& params) {
    CoincidenceParams p = params;
    if (p.threads == 0) p.threads = setup.options.threads;
    const std::uint64_t pulses = setup.sensor.scan->pulse_count(setup.options.duration);
    const std::uint64_t batch = trace_batch_pulses(setup.sensor);
    const std::uint64_t batches = (pulses + batch - 1) / batch;
    const std::size_t parts = static_cast<std::size_t>(
        std::min<std::uint64_t>(thread_count(p.threads), std::max<std::uint64_t>(1, batches)));
    std::vector<CoincidenceGrid> grids;
    grids.reserve(parts);
    for (std::size_t t = 0; t < parts; ++t) grids.emplace_back(p);
    run_parts(parts, [&](std::size_t t) {
        const std::uint64_t lo = batches * t / parts * batch;
        const std::uint64_t hi = std::min(pulses, batches * (t + 1) / parts * batch);
        add_gates(setup, events, lo, hi, grids[t]);
    });
    for (std::size_t t = 1; t < parts; ++t) grids[0].append(std::move(grids[t]));
    return std::move(grids[0]);
}

std::vector<CoincidencePoint> coincidence(const Setup& setup, std::span<const FirstEvent> events,
                                          const CoincidenceParams& params,
                                          CoincidenceStats* stats) {
    return coincidence_grid(setup, events, params).finish(stats);
}

}  // namespace mirage::render
