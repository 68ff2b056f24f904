// SPDX-License-Identifier: Apache-2.0
// Coincidence processing (docs/photon-counting.md §5): a Geiger-mode collection's photon events
// become points. Every gate of every pixel-pulse is assigned to the ground cell its line of sight
// crosses at mid-gate; per cell and height bin, the first events of the gates that looked there
// make a histogram; Coates' correction over the gates still armed at each bin turns it into the
// expected events per gate, and a bin whose count the cell's noise alone would reach with less
// than the false-alarm probability (and with at least min_events) becomes a point.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "mirage/core/point.hpp"
#include "mirage/render/point_sink.hpp"
#include "mirage/render/setup.hpp"

namespace mirage::render {

// A ground rectangle (local frame): gates whose mid-gate point falls outside are left out.
struct CoincidenceWindow {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool contains(double x, double y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

struct CoincidenceParams {
    double cell_m = 0.5;  // ground cell side
    double bin_m = 0.15;  // height bin
    std::uint32_t min_events = 3;
    double false_alarm = 1e-6;  // per bin: P(the cell's noise alone gives ≥ its count)
    // The dwell: each cell counts only its first this many gates in time (0: all), as a
    // collection that looked at it this many times would have (the seed's 60 / 240 / 480).
    std::uint32_t gates_per_cell = 0;
    std::optional<CoincidenceWindow> window;  // none: every gate
    int threads = 0;  // finishing the cells, 0: hardware concurrency (the result does not change)
    // Keep every gate and event in time order, so that finish() can take any dwell; otherwise a
    // cell keeps counts of its gates' bins and sums of its events by bin and class (a dwell then
    // comes from gates_per_cell alone; docs/photon-counting.md §5).
    bool dwells = false;
};

struct CoincidencePoint {
    double x = 0, y = 0, z = 0;           // mean of the bin's events (local frame)
    double expected = 0;                  // Coates: expected events per armed gate in the bin
    std::uint32_t events = 0, gates = 0;  // first events in the bin; gates armed there
    std::uint8_t classification = 1;      // most frequent class among its events
    double signal_share = 0;              // its events flagged signal (truth, for tests)
};

struct CoincidenceStats {
    std::uint64_t gates = 0, events = 0, cells = 0, points = 0;
    double noise_per_bin = 0;  // mean over cells of the noise estimate (events per gate-bin)
};

// One gate: the line origin + r·dir (dir unit, looking down), open for r in [r0, r1].
struct Gate {
    Eigen::Vector3d origin, dir;
    double r0 = 0, r1 = 0;
};

// Gates in structure-of-arrays form: gate i is the line (ox, oy, oz)[i] + r·(dx, dy, dz)[i],
// open for r in [r0, r1] (the receiver's range gate, the same for all).
struct GateLines {
    std::span<const double> ox, oy, oz, dx, dy, dz;
    double r0 = 0, r1 = 0;
};

// A gate's first event (the only one Coates' correction counts): its position, class, truth.
struct GateEvent {
    double x = 0, y = 0, z = 0;
    std::uint8_t classification = 1;
    bool signal = false;
};

// A pulse's first event, as FirstEventSink keeps it for coincidence().
struct FirstEvent {
    std::uint64_t pulse = 0;
    GateEvent event;
};

class CoincidenceGrid {
  public:
    explicit CoincidenceGrid(CoincidenceParams p);
    // A gate and its first event (null: none fired), in time order. ConfigError for a gate not
    // looking down, or not finite (its event included) or so far out that its cell or bins
    // overflow. Gates outside the window are left out.
    void add(const Gate& gate, const GateEvent* first);
    // Gates in time order, gate i with its first event first[i] (null: none), as add() would
    // take them one by one, except that a bad gate rejects the whole batch (before any is
    // added); the batch's arithmetic runs over whole arrays (it vectorises). Error when a span
    // of `lines` is shorter than `first`.
    void add(const GateLines& lines, std::span<const GateEvent* const> first);
    // The points, each cell counting its first `gates_per_cell` gates (0: the params' own), so
    // one grid answers several dwells (a grid made with `dwells`; Error otherwise).
    std::vector<CoincidencePoint> finish(CoincidenceStats* stats = nullptr,
                                         std::uint32_t gates_per_cell = 0) const;
    // Appends a grid of later gates (the same params): each of its columns after this one's.
    void append(CoincidenceGrid&& later);

  private:
    // A gate's bins: its first (top) and last (bottom) height bin and the one it stopped at
    // (its first event's, or bottom): armed for top − stop + 1 bins.
    struct GateBins {
        std::int32_t top, bottom, stop;
    };
    // A first event, compactly (docs/photon-counting.md §5): its gate's number in the column,
    // its bin (its gate's stop), and its position as float offsets from the cell's corner and
    // its bin's floor (exact to ~1e-7 m there; 24 bytes where the whole point in doubles took
    // 40).
    struct ColumnEvent {
        std::uint32_t gate;
        std::int32_t bin;
        float dx, dy, dz;
        std::uint8_t classification;
        bool signal;
    };
    // A column's first events of one bin and one class, summed: their count, how many were
    // signal, and their offsets (ColumnEvent's) in integer units of 2^-30 m, so that sums are
    // exact and the same in any order, on any split between threads (docs/photon-counting.md
    // §5).
    struct BinSum {
        std::int32_t bin = 0;
        std::uint8_t classification = 0;
        std::uint32_t events = 0, signal = 0;  // events 0: an empty slot of BinSums
        std::int64_t x = 0, y = 0, z = 0;
    };
    // BinSum by bin and class, in a table of open addressing (at most half full): a column has
    // a few bins of surfaces and, at night, a few of noise; by day hundreds.
    struct BinSums {
        std::vector<BinSum> slots;
        std::size_t used = 0;
        void add(const BinSum& e);
    };
    // Bins counted over the range they span while it is narrow, else listed.
    struct Tally {
        static constexpr std::size_t kWide = 4096;  // bins
        std::int32_t lo = 0;
        std::vector<std::uint32_t> counts;  // counts[k]: values lo + k
        std::vector<std::int32_t> values;   // once the range is wide
        void add(std::int32_t v) {          // inline: a value inside the range is the common case
            const auto k = static_cast<std::uint64_t>(std::int64_t(v) - lo);
            if (k < counts.size())  // (counts are empty once listed)
                ++counts[k];
            else
                add_outside(v);
        }
        void add_outside(std::int32_t v);
        void merge(const Tally& other);
        void list();
    };
    struct Column {
        std::int64_t ix = 0, iy = 0;  // the cell
        std::uint32_t count = 0;      // gates
        // Keeping gates (keep_gates()): every gate in time order. Otherwise: their top and
        // bottom bins counted and the bins they were armed for summed.
        std::vector<GateBins> gates;
        Tally tops, bottoms;
        std::uint64_t armed_bins = 0;
        std::uint32_t fired = 0;          // gates with a first event
        std::vector<ColumnEvent> events;  // keeping gates: in time order (so by gate)
        BinSums sums;                     // otherwise: their sums
    };
    // Of column c, its first g gates and their m events.
    struct Dwell {
        const Column& c;
        std::size_t g, m;
    };
    struct Scratch;  // a thread's buffers, reused from column to column
    std::size_t events_of(const Column& c, std::size_t g) const;
    void sums_by_bin(const Dwell& d, Scratch& s) const;
    static BinSum sum_of(const ColumnEvent& e);
    void finish_column(const Dwell& d, Scratch& s, std::vector<CoincidencePoint>& out,
                       double& noise) const;
    CoincidencePoint bin_point(const Column& c, std::int32_t b, std::uint32_t armed,
                               std::span<const BinSum> sums) const;
    void add_one(std::size_t i, const GateEvent* first);
    [[noreturn]] void refuse_batch(const GateLines& l, std::size_t n) const;
    bool keep_gates() const { return p_.dwells || p_.gates_per_cell > 0; }

    // The column add() used last: a frame's neighbouring pixels mostly share a cell. Never
    // carried over by a copy or a move (it points into this grid's own columns; a moved-from
    // grid forgets it too).
    struct LastColumn {
        std::int64_t key = 0;
        Column* column = nullptr;
        LastColumn() = default;
        LastColumn(const LastColumn&) {}
        LastColumn(LastColumn&& o) noexcept { o.column = nullptr; }
        LastColumn& operator=(const LastColumn&) {
            column = nullptr;
            return *this;
        }
        LastColumn& operator=(LastColumn&& o) noexcept {
            column = o.column = nullptr;
            return *this;
        }
    };

    // A batch's per-gate values, floored but not yet converted: mid-gate x and y, its cell, its
    // top and bottom bins and its event's bin (add() fills them, add_one() reads them).
    struct Floors {
        std::vector<double> mx, my, cx, cy, top, bottom, stop, qx, qy, qz;
    };

    // The column of cell (ix, iy), made if new. Columns live in a deque (stable addresses) found
    // through a table of open addressing, a power of two in size: std::unordered_map's lookup
    // takes the hash modulo a prime, an integer division per gate.
    Column& column(std::int64_t ix, std::int64_t iy);
    struct Slot {
        std::int64_t key = 0;
        std::uint32_t index = kEmpty;  // into columns_
    };
    static constexpr std::uint32_t kEmpty = ~0u;

    CoincidenceParams p_;
    Floors floors_;
    std::deque<Column> columns_;
    std::vector<Slot> slots_;
    LastColumn last_;
};

// Keeps each pulse's first event (return 1) for coincidence(), in pulse order, passing every
// point on to `next` when there is one (a LAS sink, say).
class FirstEventSink : public PointSink {
  public:
    explicit FirstEventSink(PointSink* next = nullptr) : next_(next) {}
    void write(std::span<const core::PointRecord> points) override;
    void pulses_done(std::uint64_t next_pulse) override;
    void finish() override;
    std::vector<FirstEvent> events;

  private:
    PointSink* next_;
};

// A rendered Geiger-mode collection's first events (in pulse order, as FirstEventSink keeps
// them) through the grid: every pulse of the setup's run is a gate from the receiver's minimum to
// its maximum range along its line of sight. The setup's threads share the pulses (in whole
// batches, appended in time order) and then the cells; the result does not depend on them.
CoincidenceGrid coincidence_grid(const Setup& setup, std::span<const FirstEvent> events,
                                 const CoincidenceParams& params);
// coincidence_grid(...).finish(stats).
std::vector<CoincidencePoint> coincidence(const Setup& setup, std::span<const FirstEvent> events,
                                          const CoincidenceParams& params,
                                          CoincidenceStats* stats = nullptr);

}  // namespace mirage::render
