// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/request.hpp"

namespace mirage::control {
namespace {

std::uint16_t be16(std::span<const std::uint8_t> b, std::size_t at) {
    return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

Checked fail(Exception e) {
    Checked c;
    c.exception = e;
    return c;
}

// Lengths exact per function (a short or padded PDU is malformed: exception 03, §7).
bool length_ok(Function f, std::span<const std::uint8_t> pdu) {
    switch (f) {
        case Function::ReadHolding:
        case Function::ReadInput:
        case Function::WriteSingle:
            return pdu.size() == 5;
        case Function::WriteMultiple:
            return pdu.size() >= 6 && pdu.size() == 6 + std::size_t(pdu[5]);
    }
    return false;
}

bool window_ok(std::size_t address, std::size_t count, std::size_t window) {
    return address + count <= window;
}

}  // namespace

Checked check_request(std::span<const std::uint8_t> pdu, std::size_t input_window,
                      std::size_t holding_window) {
    if (pdu.empty()) return fail(Exception::IllegalFunction);
    const auto f = static_cast<Function>(pdu[0]);
    if (f != Function::ReadHolding && f != Function::ReadInput && f != Function::WriteSingle &&
        f != Function::WriteMultiple)
        return fail(Exception::IllegalFunction);
    if (!length_ok(f, pdu)) return fail(Exception::IllegalValue);
    Checked c;
    c.request.function = f;
    c.request.address = be16(pdu, 1);
    switch (f) {
        case Function::ReadHolding:
        case Function::ReadInput: {
            c.request.count = be16(pdu, 3);
            if (c.request.count < 1 || c.request.count > kMaxReadCount)
                return fail(Exception::IllegalValue);
            const std::size_t w = f == Function::ReadInput ? input_window : holding_window;
            if (!window_ok(c.request.address, c.request.count, w))
                return fail(Exception::IllegalAddress);
            return c;
        }
        case Function::WriteSingle:
            c.request.count = 1;
            c.request.values[0] = be16(pdu, 3);
            if (!window_ok(c.request.address, 1, holding_window))
                return fail(Exception::IllegalAddress);
            return c;
        case Function::WriteMultiple: {
            c.request.count = be16(pdu, 3);
            if (c.request.count < 1 || c.request.count > kMaxWriteCount ||
                pdu[5] != 2 * c.request.count)
                return fail(Exception::IllegalValue);
            if (!window_ok(c.request.address, c.request.count, holding_window))
                return fail(Exception::IllegalAddress);
            for (std::size_t i = 0; i < c.request.count; ++i)
                c.request.values[i] = be16(pdu, 6 + 2 * i);
            return c;
        }
    }
    return fail(Exception::IllegalFunction);
}

}  // namespace mirage::control
