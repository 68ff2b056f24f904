// SPDX-License-Identifier: Apache-2.0
// libFuzzer: measured pulse-shape text. Bad content must end in ConfigError; an accepted table
// must make a shape with finite widths and unit area.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mirage/core/error.hpp"
#include "mirage/sensor/pulse_shape.hpp"
#include "mirage/sensor/pulse_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::sensor;
    PulseTable t;
    try {
        t = parse_pulse_table(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    } catch (const mirage::ConfigError&) {
        return 0;
    }
    const PulseShape s = PulseShape::tabulated(t.t_ns, t.power, "fuzz");
    if (!std::isfinite(s.sigma_ns()) || !std::isfinite(s.fwhm_ns()) || !(s.fwhm_ns() >= 0))
        __builtin_trap();
    return 0;
}
