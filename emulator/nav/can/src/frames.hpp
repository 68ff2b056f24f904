// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "bits.hpp"
#include "mirage/nav/can_frame.hpp"

// CAN frame matching and building shared by the OxTS and SBG codecs (internal).
namespace mirage::navcan::detail {

// Whether f is the configured frame `id` (0: that frame is disabled).
inline bool matches(const nav::CanFrame& f, std::uint32_t id, bool extended) {
    return id != 0 && f.id == id && f.extended == extended;
}

inline nav::CanFrame make_frame(std::uint32_t id, bool extended, std::uint8_t len,
                                const Bytes8& data) {
    nav::CanFrame f;
    f.id = id;
    f.extended = extended;
    f.len = len;
    f.data = data;
    return f;
}

}  // namespace mirage::navcan::detail
