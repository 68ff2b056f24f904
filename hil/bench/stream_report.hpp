// SPDX-License-Identifier: Apache-2.0
// `mirage stream-bench` report: what each part measured, and its markdown and JSON forms.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/udp/pacing_probe.hpp"
#include "stream_bench.hpp"

namespace mirage::hil {

inline double us(std::int64_t ns) { return static_cast<double>(ns) / 1e3; }

struct Machine {
    std::string cpu, kernel, load;
    unsigned cores = 0;
};

struct EncoderRow {
    std::string label;
    std::uint64_t packets = 0, bytes = 0, pulses = 0, aux_packets = 0;
    double seconds = 0, packets_per_s = 0, device_packets_per_s = 0;
    double emulate_packets_per_s = 0;  // as `mirage emulate` builds it (position from georef)
    double headroom() const {
        return device_packets_per_s > 0 ? packets_per_s / device_packets_per_s : 0;
    }
    double emulate_headroom() const {
        return device_packets_per_s > 0 ? emulate_packets_per_s / device_packets_per_s : 0;
    }
};

struct StreamRow {
    std::string label;
    double device_packets_per_s = 0, expected_data = 0;
    std::uint64_t data_sent = 0, data_received = 0, aux_sent = 0, aux_received = 0;
    std::uint64_t failed_sends = 0, lost = 0, unmatched = 0, ring_full = 0;
    double rx_packets_per_s = 0, rate_error = 0;  // received rate / device rate − 1
    std::uint64_t pacer_late = 0;                 // output Pacer: later than 100 µs
    double pacer_p99_us = 0, pacer_worst_us = 0;
    double send_p50_us = 0, send_p99_us = 0;  // shared sender: duration of the send calls
    std::uint64_t handed_late_1ms = 0;  // packets reaching the output > 1 ms after their deadline
    double handed_worst_ms = 0, handed_ahead_p50_ms = 0;
    double late_first_s = 0, late_last_s = 0;  // when (schedule time) the late ones fell
    LatenessSummary wire;
    double wire_late_50us_share = 0;  // of the received packets, later than 50 µs
    std::uint64_t pulses = 0, points = 0;
    // Thread CPU seconds: render workers (rays + trace + shade) and the writer thread in the sink
    // (packet encoding, position / IMU fixes, the Pacer's final spin, send system calls).
    double cpu_render_s = 0, cpu_output_s = 0;
    bool real_time = false;
    std::string error;
};

struct StreamsResult {
    std::vector<StreamRow> rows;
    std::string rig;  // the rig file streamed (stream-bench --rig), else the three cases
    double wall_s = 0, cpu_s = 0;
    int render_threads = 1;
    std::size_t chunk_pulses = 0;
    int fifo_priority = 0;
    bool shared = true;  // one SharedSender thread for all streams (else a Pacer per stream)
    bool fifo = false;   // the sending thread(s) got SCHED_FIFO
    std::string fifo_error;
    // Shared sender: its thread's CPU seconds, wake-ups by submits, submits held back by the
    // horizon / by a full queue.
    double sender_cpu_s = 0;
    int spin_margin_us = 50;
    double horizon_ms = 0;
    std::uint64_t sender_wakeups = 0, horizon_waits = 0, full_waits = 0;
    double wake_late_p50_us = 0, wake_late_p99_us = 0;  // its timed sleeps' overshoot
    // --keep-awake: SCHED_IDLE spinners kept the CPUs out of idle (threads; 0: not asked for)
    std::size_t keep_awake_threads = 0;
    std::string keep_awake_warning;
    std::string trajectory;
    double render_lead_ms = 0;  // how far the renderers may run ahead (as emulate)
    double cpu_percent() const { return wall_s > 0 ? 100.0 * cpu_s / wall_s : 0; }
};

struct ProbeRow {
    std::string label;
    bool ran = false;
    std::string note;
    udp::PacingProbeReport report;
};

// The machine's floor, measured in the same run just before and just after the streams: the
// delays of a thread that only spins on the clock (what mirage-sched-gaps measures).
struct Floor {
    double seconds = 0;     // spun in all (0: not measured)
    double share_50us = 0;  // instants a send due then would reach more than 50 µs late
    double p99_us = 0;      // the delay 1 % of instants exceed (10 µs and below unresolved)
    double worst_us = 0;    // the longest gap
};

struct Report {
    Machine machine;
    Floor floor;        // with --keep-awake: measured with the spinners on, as the streams ran
    Floor floor_plain;  // --keep-awake only: measured without them (seconds 0 otherwise)
    std::string seconds;
    bool quick = false;
    double scene_seconds = 0;
    std::vector<EncoderRow> encoder;
    StreamsResult streams;
    std::vector<ProbeRow> probes;
};

// streams.md: tables and the issue-3 targets.
std::string stream_markdown(const Report& r);
// streams.json. A figure that is not finite is written as null.
std::string stream_json(const Report& r);

}  // namespace mirage::hil
