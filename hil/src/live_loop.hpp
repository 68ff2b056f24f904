// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>

#include "job.hpp"
#include "mirage/core/time.hpp"
#include "mirage/navio/nav_input.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/udp/lateness_histogram.hpp"
#include "mirage/wire/setup.hpp"

namespace mirage::hil {

struct LiveOptions {
    // Packets leave at their firing time + this, on the host clock mapped from INS time: room
    // to render a window after its last firing.
    core::Nanos pipeline_delay{std::chrono::microseconds(250)};
    core::Nanos duration{0};  // 0: until stopped
    bool status_line = true;
};

struct LiveTotals {
    std::uint64_t windows = 0, stale_windows = 0, stale_periods = 0;
    std::uint64_t packets = 0, bytes = 0, points = 0;
    udp::LatenessHistogram latency{core::Nanos{2'000'000}};  // INS message -> first packet
    double seconds = 0;
};

// The real-time loop of `mirage live`: renders one data packet's worth of pulses at a time, as
// soon as its last firing time has passed on the INS clock (so every message up to then is in
// the pose buffer), with poses interpolated — or extrapolated within the buffer's horizon — at
// each firing; a window without a pose (stale navigation) still sends its packets, with no
// returns. Pulse 0 fires at job.options.start (INS GPS time).
LiveTotals run_live(Job& job, wire::Packetizer& packetizer, output::PacketOutput& out,
                    std::size_t pulses_per_window, navio::NavInput& nav,
                    const navpose::PoseBuffer& poses, const LiveOptions& opt,
                    const std::atomic<bool>& stop, std::uint64_t& packets_seen,
                    std::uint64_t& bytes_seen, std::int64_t& first_send_ns);

}  // namespace mirage::hil
