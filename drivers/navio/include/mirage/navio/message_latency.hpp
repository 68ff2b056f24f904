// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mirage/navio/nav_input.hpp"
#include "mirage/navpose/pose_buffer.hpp"
#include "mirage/udp/lateness_histogram.hpp"

namespace mirage::navio {

// INS message -> packet latency as named: for each navigation message applied, the time from
// its arrival to the send of the first data packet rendered with a pose from it (interpolation
// uses both bracketing samples, extrapolation the newest: navpose::PoseWindow::used). Fed by
// the live loop in order: messages applied, the windows rendered, the data packets sent. A data
// packet holds the pulses of every window rendered since the previous one, so it times all the
// messages those windows used. Single-threaded.
class MessageLatency {
  public:
    // Messages applied to the pose buffer (NavInput::take_applied): from now on timed.
    void applied(const std::vector<AppliedMessage>& messages);
    // The messages a rendered window's poses came from; messages not applied through
    // applied() (a backlog before timing began) are not timed.
    void rendered(const std::vector<navpose::UsedMessage>& used);
    // A data packet was sent at host CLOCK_MONOTONIC `sent_ns`.
    void data_packet_sent(std::int64_t sent_ns);

    const udp::LatenessHistogram& latency() const { return latency_; }
    std::uint64_t messages() const { return messages_; }  // applied() so far
    // Messages not in any packet (yet): superseded when each track a message updated had a newer
    // sample used first (windows use the newest samples up to their time, so it never will be);
    // the others are still waiting (e.g. at the end of a run).
    struct Unused {
        std::uint64_t superseded = 0, waiting = 0;
    };
    Unused unused() const;

  private:
    struct Pending {
        std::int64_t arrival_ns = 0;
        bool position = false, attitude = false;
        bool rendered = false;  // used by a window whose packet has not been sent yet
    };
    udp::LatenessHistogram latency_{core::Nanos{2'000'000}};
    std::uint64_t messages_ = 0;
    std::unordered_map<std::uint64_t, Pending> pending_;  // by message sequence number
    std::vector<std::uint64_t> due_;                      // rendered, waiting for a packet
    std::uint64_t newest_used_[2] = {0, 0};               // by track: position, attitude
    bool any_used_[2] = {false, false};
};

}  // namespace mirage::navio
