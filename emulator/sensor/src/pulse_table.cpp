// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/pulse_table.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mirage/core/error.hpp"
#include "mirage/sensor/pulse_shape.hpp"

namespace mirage::sensor {
namespace {

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
    throw ConfigError("pulse shape '" + source + "'" +
                      (line > 0 ? ": line " + std::to_string(line) : std::string()) + ": " + what);
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == ','; }

// The next number of `s` from `at` (blanks and one comma before it skipped), or false.
bool next_number(std::string_view s, std::size_t& at, double& out) {
    while (at < s.size() && is_blank(s[at])) ++at;
    if (at == s.size()) return false;
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data() + at, end, out);
    if (r.ec != std::errc() || !std::isfinite(out)) return false;
    at = static_cast<std::size_t>(r.ptr - s.data());
    return true;
}

}  // namespace

PulseTable parse_pulse_table(std::string_view text, const std::string& source) {
    if (text.size() > kMaxPulseTableBytes)
        fail(source, 0, "larger than " + std::to_string(kMaxPulseTableBytes) + " bytes");
    PulseTable t;
    std::size_t line = 0;
    while (!text.empty()) {
        ++line;
        const std::size_t nl = text.find('\n');
        std::string_view l = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
        if (const std::size_t hash = l.find('#'); hash != std::string_view::npos)
            l = l.substr(0, hash);
        std::size_t at = 0;
        while (at < l.size() && is_blank(l[at])) ++at;
        if (at == l.size()) continue;
        double time = 0, power = 0;
        if (!next_number(l, at, time) || !next_number(l, at, power))
            fail(source, line, "expected two finite numbers: time_ns, relative_power");
        while (at < l.size() && is_blank(l[at])) ++at;
        if (at != l.size()) fail(source, line, "more than two values");
        if (t.t_ns.size() == kMaxPulseTableSamples)
            fail(source, line, "more than " + std::to_string(kMaxPulseTableSamples) + " samples");
        t.t_ns.push_back(time);
        t.power.push_back(power);
    }
    t.fwhm_ns = PulseShape::tabulated(t.t_ns, t.power, source).fwhm_ns();  // and its checks
    return t;
}

PulseTable load_pulse_table(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw IoError("pulse shape '" + path + "': not a readable file");
    if (std::filesystem::file_size(path, ec) > kMaxPulseTableBytes)
        fail(path, 0, "larger than " + std::to_string(kMaxPulseTableBytes) + " bytes");
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in && !in.eof()) throw IoError("pulse shape '" + path + "': cannot read");
    return parse_pulse_table(text.str(), path);
}

}  // namespace mirage::sensor
