// SPDX-License-Identifier: Apache-2.0
// libFuzzer entry: the first byte picks a target, the rest is its input. Frames are built from
// 13-byte records (4 id, 1 flags, 8 data) so the CAN decoders see arbitrary IDs, DLCs and data.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

#include "mirage/navcan/candump.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"
#include "mirage/navcan/slcan.hpp"

using namespace mirage;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::uint8_t which = data[0] % 4;
    const std::span<const std::uint8_t> in(data + 1, size - 1);
    volatile std::uint64_t sink = 0;
    auto on_sample = [&](const nav::NavSample& s) { sink = sink + s.fields; };
    if (which == 0 || which == 1) {
        navcan::OxtsCanDecoder oxts;
        navcan::SbgCanDecoder sbg;
        for (std::size_t i = 0; i + 13 <= in.size(); i += 13) {
            nav::CanFrame f;
            std::uint32_t id = 0;
            std::memcpy(&id, in.data() + i, 4);
            const std::uint8_t flags = in[i + 4];
            // Bias IDs into the decoders' ranges half of the time.
            f.id =
                (flags & 0x80) ? id & 0x1FFF'FFFFu : (which == 0 ? 0x600u : 0x100u) + (id & 0x3Fu);
            f.extended = (flags & 0x40) != 0 && (flags & 0x80) != 0;
            f.rtr = (flags & 0x30) == 0x30;
            f.len = static_cast<std::uint8_t>(flags & 0x0F);  // 0..15: out-of-range DLCs too
            if (f.len > 8) f.len = 8;
            std::memcpy(f.data.data(), in.data() + i + 5, 8);
            if (which == 0) {
                oxts.feed(nav::StampedCanFrame{static_cast<std::int64_t>(id), f}, on_sample);
            } else {
                sbg.feed(f, on_sample);
            }
        }
        oxts.flush(on_sample);
        sbg.flush(on_sample);
    } else if (which == 2) {
        navcan::CandumpRecord rec;
        const std::string_view text(reinterpret_cast<const char*>(in.data()), in.size());
        if (navcan::parse_candump_line(text, rec) == navcan::CandumpStatus::Ok) {
            // Round trip: what we format must parse back to the same frame.
            navcan::CandumpRecord again;
            const auto line = navcan::format_candump_line(rec, true);
            if (navcan::parse_candump_line(line, again) != navcan::CandumpStatus::Ok ||
                !(again.stamped.frame == rec.stamped.frame)) {
                __builtin_trap();
            }
        }
    } else {
        navcan::SlcanParser parser;
        parser.feed(in, [&](const navcan::SlcanEvent& ev) {
            if (ev.kind == navcan::SlcanEvent::Kind::Frame) {
                navcan::SlcanEvent back;
                std::string enc = navcan::slcan_encode(ev.frame);
                enc.pop_back();
                if (!navcan::slcan_parse_line(enc, back) || !(back.frame == ev.frame)) {
                    __builtin_trap();
                }
            }
            sink = sink + static_cast<std::uint64_t>(ev.kind);
        });
    }
    return 0;
}
