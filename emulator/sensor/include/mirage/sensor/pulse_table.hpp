// SPDX-License-Identifier: Apache-2.0
// A measured pulse shape from a text file (sensor YAML `beam.pulse_shape: <file>`,
// docs/sensors.md §3): one "time_ns, relative_power" pair per line, comma or blanks between,
// `#` to the end of a line a comment, blank lines ignored.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace mirage::sensor {

struct PulseTable {
    std::vector<double> t_ns, power;
    double fwhm_ns = 0;  // of the shape the table makes (PulseShape::tabulated)
};

inline constexpr std::size_t kMaxPulseTableBytes = 1 << 20;
inline constexpr std::size_t kMaxPulseTableSamples = 100'000;

// Checked in order: size (≤ kMaxPulseTableBytes), each line's two finite numbers, the sample
// count (2 … kMaxPulseTableSamples), then the shape (PulseShape::tabulated: times increasing,
// powers ≥ 0, an area). ConfigError naming `source` and the line otherwise.
PulseTable parse_pulse_table(std::string_view text, const std::string& source);
// The same from a regular file; IoError if it cannot be read, ConfigError as above.
PulseTable load_pulse_table(const std::string& path);

}  // namespace mirage::sensor
