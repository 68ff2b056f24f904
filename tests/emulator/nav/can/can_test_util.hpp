// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/navcan/candump.hpp"

namespace mirage::navcan::test {

// Frame from candump text `601#081EAE1C184FDD06`.
inline nav::CanFrame cf(const std::string& text) {
    CandumpRecord rec;
    const auto st = parse_candump_line("(0.000000) t " + text, rec);
    if (st != CandumpStatus::Ok) return nav::CanFrame{};
    return rec.stamped.frame;
}

inline std::string hex_of(const nav::CanFrame& f) {
    const std::string line = format_candump_line(0, "x", f);
    return line.substr(line.rfind(' ') + 1);
}

}  // namespace mirage::navcan::test
