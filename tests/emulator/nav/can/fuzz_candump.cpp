// SPDX-License-Identifier: Apache-2.0
// libFuzzer: candump -L log text, line by line, through the line parser. Every line the parser
// accepts must format back to a line that parses to the same frame, time and interface.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mirage/navcan/candump.hpp"

using namespace mirage;

namespace {

void one_line(std::string_view text) {
    navcan::CandumpRecord rec;
    if (navcan::parse_candump_line(text, rec) != navcan::CandumpStatus::Ok) return;
    if (rec.stamped.frame.len > 8 || rec.interface.size() > navcan::kCandumpMaxIfname)
        __builtin_trap();
    navcan::CandumpRecord again;
    const auto line = navcan::format_candump_line(rec, true);
    if (navcan::parse_candump_line(line, again) != navcan::CandumpStatus::Ok ||
        !(again.stamped.frame == rec.stamped.frame) || again.interface != rec.interface ||
        (rec.stamped.time_ns >= 0 && again.stamped.time_ns != rec.stamped.time_ns))
        __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view text(reinterpret_cast<const char*>(data), size);
    while (!text.empty()) {
        const std::size_t nl = text.find('\n');
        one_line(text.substr(0, nl));
        if (nl == std::string_view::npos) break;
        text.remove_prefix(nl + 1);
    }
    return 0;
}
