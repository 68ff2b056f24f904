// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the control plane's request handler (docs/control.md §3). Input: a sequence of
// records [1 byte: ms to advance the clock][1 byte: PDU length n][n bytes: PDU]. Each PDU is
// checked and, if well formed, answered by the model; the watchdog ticks between requests.
// Invariants: nothing crashes, a read never writes past its count, the state stays one of five.
#include <array>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "mirage/control/control_model.hpp"

using namespace mirage::control;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Identity id;
    id.sensors = 3;
    id.scenarios = 2;
    ControlModel model(id, {}, 200);
    std::int64_t now = 0;
    std::array<std::uint16_t, kMaxReadCount + 1> out{};
    std::size_t at = 0;
    while (at + 2 <= size) {
        now += std::int64_t{data[at]} * 1'000'000;
        const std::size_t n = data[at + 1];
        at += 2;
        if (at + n > size) break;
        const Checked c =
            check_request({data + at, n}, model.input_window(), model.holding_window());
        at += n;
        out.back() = 0xBEEF;
        if (c.exception == Exception::None)
            (void)model.handle(c.request, now, std::span(out).first(kMaxReadCount));
        else
            model.count_refused();
        if (out.back() != 0xBEEF) std::abort();
        model.tick(now);
        if (static_cast<std::uint16_t>(model.state()) > 4) std::abort();
    }
    return 0;
}
