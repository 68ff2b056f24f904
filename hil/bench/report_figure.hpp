// SPDX-License-Identifier: Apache-2.0
// A figure of a text report that is never NaN or Inf on the page.
#pragma once
#include <fmt/format.h>

#include <cmath>

namespace mirage::hil {

// Formats as the double it holds, with the same format spec ("{:.2f}"), or as "n/a" when that is
// not finite: NaN and Inf never reach a report file.
struct Figure {
    double value;
};
inline Figure fig(double v) { return {v}; }

}  // namespace mirage::hil

template <>
struct fmt::formatter<mirage::hil::Figure> : fmt::formatter<double> {
    template <typename Context>
    auto format(mirage::hil::Figure f, Context& ctx) const -> decltype(ctx.out()) {
        if (!std::isfinite(f.value)) return fmt::format_to(ctx.out(), "n/a");
        return fmt::formatter<double>::format(f.value, ctx);
    }
};
