// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>

#include "mirage/core/time.hpp"
#include "mirage/udp/lateness_histogram.hpp"

namespace mirage::udp {

struct PacingProbeConfig {
    std::uint32_t rate_hz = 10'000;  // packets per second on the sensor clock
    std::uint64_t packets = 2'000;
    std::size_t payload_bytes = 1206;
    core::Nanos late_threshold{50'000};
    int fifo_priority = 0;  // > 0: run the sending thread SCHED_FIFO at this priority (if allowed)
};

struct PacingProbeReport {
    std::uint64_t scheduled = 0, received = 0, failed_sends = 0;
    core::Nanos schedule_span{0};  // deadline of the last packet − the first's
    core::Nanos received_span{0};  // kernel receive time of the last packet − the first's
    // Least lateness among the last tenth of the packets − least among the first tenth: the
    // clock drift over the run. Delays only ever add lateness, so the least of many packets is
    // the clock relation itself, whatever stalls a loaded machine causes in between.
    core::Nanos drift{0};
    LatenessHistogram wire;   // kernel receive timestamp − scheduled deadline
    LatenessHistogram pacer;  // pacer wake-up − deadline (before the send system call)
};

// Sends `packets` numbered datagrams over loopback (UdpSender -> UdpReceiver on 127.0.0.1, port
// 0) paced by a Pacer at rate_hz, and measures each packet's lateness against its schedule from
// SO_TIMESTAMPNS kernel timestamps (CLOCK_REALTIME, mapped onto the pacer's CLOCK_MONOTONIC
// deadlines through an offset sampled at the start). Throws IoError if sockets cannot be set up.
PacingProbeReport run_pacing_probe(const PacingProbeConfig& config);

// "packets 2000/2000, span 199.900 ms (schedule 199.900 ms), lateness p50 .. p99 .. max .. µs".
// Puts the calling thread in SCHED_FIFO at `priority`; false (and why) when not permitted.
bool set_realtime_priority(int priority, std::string& why);

std::string format_report(const PacingProbeReport& report);

}  // namespace mirage::udp
