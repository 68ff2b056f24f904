// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "mirage/pcap/pcap.hpp"
#include "mirage/replay/impairer.hpp"
#include "mirage/udp/lateness_histogram.hpp"

namespace mirage::replay {

struct ReplayConfig {
    std::string path;                                 // classic pcap or pcapng
    std::string host = "127.0.0.1";                   // every datagram goes to this IPv4 host
    std::map<std::uint16_t, std::uint16_t> port_map;  // capture dst port -> sent port
    double speed = 1.0;                               // 0: as fast as possible (batched)
    std::uint32_t loops = 1;                          // passes over the file (0: endless)
    std::int64_t from_ns = 0;                         // skip datagrams earlier than first + from_ns
    std::int64_t until_ns = -1;                       // stop at first + until_ns (-1: end of file)
    std::string filter;  // libpcap filter expression (pcap-filter(7)); empty: all
    ImpairmentConfig impair;
    std::int64_t lead_ns = 2'000'000;  // the first datagram is due this long after the start
    std::int64_t spin_ns = 1'000'000;  // sleep to this long before a deadline, then spin
    int send_buffer_bytes = 4 << 20;
};

struct ReplaySummary {
    std::uint64_t datagrams_read = 0;  // UDP datagrams taken from the file (all passes)
    std::uint64_t out_of_range = 0;    // outside --from / --until
    std::uint64_t packets = 0;         // sent (accepted by the kernel)
    std::uint64_t bytes = 0;           // payload bytes sent
    std::uint64_t failed = 0;          // refused by the kernel
    std::uint64_t syscalls = 0;
    std::uint64_t gso_messages = 0;  // runs of datagrams sent as one UDP GSO message
    std::uint64_t filtered = 0;      // frames the filter rejected
    std::array<std::uint64_t, pcap::kFrameStatusCount> frames{};  // by FrameStatus, all passes
    ImpairmentCounters impair;
    udp::LatenessHistogram lateness{udp::LatenessHistogram(core::Nanos{20'000})};
    std::int64_t schedule_ns = 0;  // last deadline − first (host time)
    // From the start of the first send call to the return of the last (host time): a capture
    // sent in one call still takes the time of that call.
    std::int64_t elapsed_ns = 0;
    // CLOCK_MONOTONIC instant the capture's first datagram was due on the first pass: datagram
    // i of a 1x replay is due at anchor_ns + (t_i − t_first), so receivers can check the timing.
    std::int64_t anchor_ns = -1;
    std::uint32_t passes = 0;
    bool stopped = false;  // the stop flag ended it
    bool top_speed = false;
    int link_type = 0;
    bool link_supported = true;
    std::string error;  // read error of the file ("record at byte N: ...")
    std::int64_t error_offset = -1;
};

// Replays the UDP payloads of a capture with its timing: each datagram is due at
// anchor + (t − t_first) / speed on CLOCK_MONOTONIC (absolute deadlines, so waiting errors never
// add up to drift); the thread sleeps to spin_ns before a deadline and spins the rest. Datagrams
// already due are sent together with one sendmmsg. Lateness (time of the send call − deadline)
// goes into the summary's histogram. A read error ends the replay after everything before it was
// sent (error / error_offset). Throws ConfigError / IoError for setup problems (file, host,
// filter). `stop` (optional) ends it early; `on_progress` is called about once a second.
ReplaySummary replay(const ReplayConfig& config, const std::atomic<bool>* stop = nullptr,
                     const std::function<void(const ReplaySummary&)>& on_progress = {});

// Multi-line human summary: packets, bytes, skipped by reason, impairments, timing error.
std::string format_summary(const ReplaySummary& s);

}  // namespace mirage::replay
