// SPDX-License-Identifier: Apache-2.0
// `mirage emulate` on the network: the live stream reaches a loopback receiver (port 0), paced on
// the sensor clock.
#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "mirage/udp/udp_receiver.hpp"

namespace mirage::test {
namespace {

TEST(EmulateLive, live_stream_reaches_a_loopback_receiver_paced_in_real_time) {
    udp::UdpReceiver rx;  // port 0: the kernel picks a free port
    const auto r = run_mirage(
        "emulate --sensor vlp16 --pose 0,0,1.8 --duration 0.5 --realtime "
        "--no-status --position-port 0 --to 127.0.0.1 --data-port " +
        std::to_string(rx.port()));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // Everything was queued in the socket buffer while the command ran (0.45 MB < 4 MB).
    udp::ReceivedDatagram d;
    std::size_t n = 0;
    std::int64_t first = 0, last = 0;
    while (rx.receive(d, std::chrono::milliseconds(200))) {
        if (n == 0) first = d.kernel_time_ns;
        last = d.kernel_time_ns;
        EXPECT_EQ(d.payload.size(), 1206u);
        ++n;
    }
    EXPECT_NEAR(double(n), 377.0, 1.0);  // 0.5 s × 754 packets/s
    // Paced, not dumped: the packets arrive over the 0.5 s they span on the sensor clock.
    EXPECT_GT(double(last - first) * 1e-9, 0.45);
    EXPECT_LT(double(last - first) * 1e-9, 0.60);
}

}  // namespace
}  // namespace mirage::test
