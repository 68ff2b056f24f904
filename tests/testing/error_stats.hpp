// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace mirage::test {

// RMS and largest absolute value of a stream of errors.
struct ErrorStats {
    double sum_sq = 0, max_abs = 0;
    std::size_t n = 0;
    void add(double e) {
        sum_sq += e * e;
        max_abs = std::max(max_abs, std::abs(e));
        ++n;
    }
    double rms() const { return n ? std::sqrt(sum_sq / static_cast<double>(n)) : 0.0; }
};

}  // namespace mirage::test
