// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/lateness_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::udp {

void LatenessHistogram::add(core::Nanos lateness) {
    const std::int64_t ns = lateness.count();
    if (count_ == 0) {
        worst_ns_ = best_ns_ = ns;
    } else {
        worst_ns_ = std::max(worst_ns_, ns);
        best_ns_ = std::min(best_ns_, ns);
    }
    ++count_;
    if (ns > threshold_ns_) ++late_;
    const std::int64_t bin = std::clamp<std::int64_t>(ns / kBinNs, 0, std::int64_t{kBins});
    ++bins_[static_cast<std::size_t>(bin)];
}

void LatenessHistogram::clear() {
    bins_.fill(0);
    count_ = late_ = 0;
    worst_ns_ = best_ns_ = 0;
}

core::Nanos LatenessHistogram::percentile(double q) const {
    if (count_ == 0) return core::Nanos{0};
    // Rank of the quantile sample, 1-based (nearest-rank definition).
    const auto rank = static_cast<std::uint64_t>(
        std::max(1.0, std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_))));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
        seen += bins_[i];
        if (seen >= rank)
            return core::Nanos{std::min(static_cast<std::int64_t>(i + 1) * kBinNs, worst_ns_)};
    }
    return core::Nanos{worst_ns_};
}

std::uint64_t LatenessHistogram::count_from(core::Nanos t) const {
    const std::int64_t first = std::clamp<std::int64_t>(t.count() / kBinNs, 0, std::int64_t{kBins});
    std::uint64_t n = 0;
    for (auto i = static_cast<std::size_t>(first); i <= kBins; ++i) n += bins_[i];
    return n;
}

}  // namespace mirage::udp
