// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>

#include "mirage/core/time.hpp"

namespace mirage::udp {

// Lateness (actual − scheduled) statistics without allocation per sample: 1 µs bins up to
// 10 ms, one overflow bin; the worst and best values are kept exactly. Early samples (negative
// lateness) fall in bin 0.
class LatenessHistogram {
  public:
    static constexpr std::size_t kBins = 10'000;
    static constexpr std::int64_t kBinNs = 1'000;

    explicit LatenessHistogram(core::Nanos late_threshold = core::Nanos{100'000})
        : threshold_ns_(late_threshold.count()) {}

    void add(core::Nanos lateness);
    void clear();

    std::uint64_t count() const { return count_; }
    std::uint64_t late() const { return late_; }  // samples later than the threshold
    core::Nanos threshold() const { return core::Nanos{threshold_ns_}; }
    core::Nanos worst() const { return core::Nanos{worst_ns_}; }
    core::Nanos best() const { return core::Nanos{best_ns_}; }
    // Upper edge of the bin holding quantile q in [0, 1] (worst() beyond the last bin); 0 when
    // empty. Resolution 1 µs.
    core::Nanos percentile(double q) const;
    // Samples at or later than t, t rounded down to the 1 µs bins (beyond the last bin: the
    // samples there, whatever t).
    std::uint64_t count_from(core::Nanos t) const;

  private:
    std::array<std::uint64_t, kBins + 1> bins_{};
    std::int64_t threshold_ns_;
    std::uint64_t count_ = 0, late_ = 0;
    std::int64_t worst_ns_ = 0, best_ns_ = 0;
};

}  // namespace mirage::udp
