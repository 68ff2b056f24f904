// SPDX-License-Identifier: Apache-2.0
// libFuzzer: slcan adapter output through the stream parser (any bytes, resynchronising) and each
// line through the one-line parser. A frame parsed either way must encode back to the same frame.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "mirage/navcan/slcan.hpp"

using namespace mirage;

namespace {

void round_trip(const nav::CanFrame& f) {
    if (f.len > 8 || f.id > (f.extended ? 0x1FFFFFFFu : 0x7FFu)) __builtin_trap();
    navcan::SlcanEvent back;
    std::string enc = navcan::slcan_encode(f);
    enc.pop_back();  // the '\r'
    if (!navcan::slcan_parse_line(enc, back) || !(back.frame == f)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    navcan::SlcanParser parser;
    parser.feed(std::span(data, size), [&](const navcan::SlcanEvent& ev) {
        if (ev.kind == navcan::SlcanEvent::Kind::Frame) round_trip(ev.frame);
    });
    std::string_view text(reinterpret_cast<const char*>(data), size);
    while (!text.empty()) {
        const std::size_t cr = text.find('\r');
        navcan::SlcanEvent ev;
        if (navcan::slcan_parse_line(text.substr(0, cr), ev) &&
            ev.kind == navcan::SlcanEvent::Kind::Frame)
            round_trip(ev.frame);
        if (cr == std::string_view::npos) break;
        text.remove_prefix(cr + 1);
    }
    return 0;
}
