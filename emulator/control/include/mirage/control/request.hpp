// SPDX-License-Identifier: Apache-2.0
// A Modbus request PDU checked before anything answers it (docs/control.md §3): length for the
// function code, then address window and count, then byte count. Only what passes reaches the
// model and libmodbus's reply (which has read out of bounds on requests whose lengths and counts
// disagree). Never throws.
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "mirage/control/register_map.hpp"

namespace mirage::control {

enum class Function : std::uint8_t {
    ReadHolding = 0x03,
    ReadInput = 0x04,
    WriteSingle = 0x06,
    WriteMultiple = 0x10,
};

inline constexpr std::size_t kMaxReadCount = 125;   // §6.3
inline constexpr std::size_t kMaxWriteCount = 123;  // §6.12

struct Request {
    Function function = Function::ReadHolding;
    std::uint16_t address = 0;
    std::uint16_t count = 0;
    std::array<std::uint16_t, kMaxWriteCount> values{};  // writes: `count` values
};

struct Checked {
    Exception exception = Exception::None;  // None: `request` is well formed
    Request request;
};

// `pdu`: function code and data, without the TCP or RTU framing. Windows: the register counts
// the server maps (input_registers / holding_registers of its sensor count).
Checked check_request(std::span<const std::uint8_t> pdu, std::size_t input_window,
                      std::size_t holding_window);

}  // namespace mirage::control
