// SPDX-License-Identifier: Apache-2.0
#pragma once
// CAN frames as fuzz input: 14-byte records, id (u32 LE: bit 31 extended, bit 30 RTR), DLC
// (low nibble; 9..15 read as 8), 8 data bytes, time step in ms since the previous frame. The
// seed generator writes encoder output in this form.
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "mirage/nav/can_frame.hpp"

namespace mirage::navcan::test {

inline constexpr std::size_t kCanRecordSize = 14;

template <class Fn>
void for_each_record(std::span<const std::uint8_t> in, Fn&& fn) {
    std::int64_t t_ns = 1'700'000'000'000'000'000;
    for (std::size_t i = 0; i + kCanRecordSize <= in.size(); i += kCanRecordSize) {
        const std::uint8_t* r = in.data() + i;
        std::uint32_t id = 0;
        std::memcpy(&id, r, 4);
        nav::StampedCanFrame f;
        f.frame.extended = (id & 0x8000'0000u) != 0;
        f.frame.rtr = (id & 0x4000'0000u) != 0;
        f.frame.id = id & (f.frame.extended ? 0x1FFF'FFFFu : 0x7FFu);
        const auto dlc = static_cast<std::uint8_t>(r[4] & 0x0F);
        f.frame.len = dlc > 8 ? std::uint8_t{8} : dlc;
        std::memcpy(f.frame.data.data(), r + 5, 8);
        t_ns += std::int64_t{r[13]} * 1'000'000;
        f.time_ns = t_ns;
        fn(static_cast<const nav::StampedCanFrame&>(f));
    }
}

inline void append_record(std::vector<std::uint8_t>& out, const nav::CanFrame& f,
                          std::uint8_t step_ms) {
    const std::uint32_t id = f.id | (f.extended ? 0x8000'0000u : 0u) | (f.rtr ? 0x4000'0000u : 0u);
    const std::size_t at = out.size();
    out.resize(at + kCanRecordSize);
    std::memcpy(out.data() + at, &id, 4);
    out[at + 4] = f.len;
    std::memcpy(out.data() + at + 5, f.data.data(), 8);
    out[at + 13] = step_ms;
}

}  // namespace mirage::navcan::test
