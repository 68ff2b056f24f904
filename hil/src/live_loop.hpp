// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "job.hpp"
#include "mirage/control/sensor_faults.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/navio/message_latency.hpp"
#include "mirage/navio/nav_input.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/udp/lateness_histogram.hpp"
#include "mirage/wire/setup.hpp"

namespace mirage::hil {

// When packets leave is the output's business: the caller anchors it at firing time +
// --pipeline-delay-us.
struct LiveOptions {
    core::Nanos duration{0};  // 0: until stopped
    bool status_line = true;
    // Time the INS messages to the packets (one session per NavInput may: the applied messages
    // are taken from it).
    bool message_latency = true;
    // Faults a controller injects (docs/control.md §5): stale navigation renders no window,
    // frozen navigation holds the pose of the moment it froze. Null: none.
    const control::FaultCell* faults = nullptr;
    // Before the first pose (docs/live-navigation.md §1): end the run when one arrives, and pace
    // on this host-clock offset (CLOCK_MONOTONIC − GPS time from CLOCK_REALTIME) instead of the
    // INS's, which may not be known yet.
    bool until_first_pose = false;
    std::optional<std::int64_t> host_clock_offset_ns;
};

// How long a command waits for the first full pose before it streams without returns.
inline constexpr double kFirstPoseSettleS = 1.0;

// The frame navigation is mapped into: the scene's georeference, or a tangent plane at
// `origin` (lat, lon, h). `who` names the command in errors.
navpose::NavFrame live_frame(const Job& job, const std::vector<double>& origin,
                             const std::string& who);
// Pulses the live loop renders at a time (whole firing groups): a data packet's, split evenly
// (so a packet's last pulse ends a window) into the fewest windows that each span at most twice
// the pipeline delay. A packet is due `delay` after its last firing and its last window can
// only be rendered then; more windows wake the loop more often beside the sending thread
// (docs/live-navigation.md §1).
std::size_t live_window_pulses(const Job& job, double packets_per_second, core::Nanos delay);
// No full pose arrived within the first-navigation timeout.
class FirstPoseTimeout : public IoError {
  public:
    using IoError::IoError;
};

// Waits for the first full pose; throws FirstPoseTimeout naming `nav_uri` and the counters after
// `timeout_s`; nullopt when `stop` was set first.
std::optional<core::GpsTime> wait_first_pose(const navpose::PoseBuffer& poses,
                                             const navio::NavInput& nav, const std::string& nav_uri,
                                             double timeout_s, const std::atomic<bool>& stop,
                                             const std::string& who);
// True once the pose buffer holds a pose; false after `seconds` or when `stop` is set.
bool await_first_pose(const navpose::PoseBuffer& poses, const std::atomic<bool>& stop,
                      double seconds);
// Before the INS has a clock, pulse 0 fires this far ahead on the host's GPS time.
inline constexpr core::Nanos kHostPulse0Lead{20'000'000};
// `lo` for the run before the first pose: ends at the first pose, paced on the host's clock
// (`host_offset_ns`: CLOCK_MONOTONIC − GPS), no INS messages to time.
LiveOptions before_first_pose(LiveOptions lo, std::int64_t host_offset_ns);
// Pulse 0's INS time (ns): a serial line may hold a backlog of old messages, so 250 ms pass for
// the INS-to-host offset (lower envelope of arrival − INS time) to settle on messages arriving
// live; then the present INS time + 20 ms, whole ms.
std::int64_t live_pulse0_ns(const navio::NavInput& nav);

struct LiveTotals {
    std::uint64_t windows = 0, stale_windows = 0, stale_periods = 0;
    std::uint64_t packets = 0, bytes = 0, points = 0;
    // Per navigation message applied after pulse 0: its arrival -> the send of the first data
    // packet rendered with a pose from it (interpolation uses both samples, extrapolation the
    // newest).
    udp::LatenessHistogram latency{core::Nanos{2'000'000}};
    std::uint64_t messages = 0;    // messages applied after pulse 0
    std::uint64_t superseded = 0;  // never in a packet: newer samples of their tracks came first
    std::uint64_t waiting_at_end = 0;  // not yet in a packet when the run ended
    double seconds = 0;
};

// The real-time loop of `mirage live`: renders one data packet's worth of pulses at a time, as
// soon as its last firing time has passed on the INS clock (so every message up to then is in
// the pose buffer), with poses interpolated — or extrapolated within the buffer's horizon — at
// each firing; a window without a pose (stale navigation) still sends its packets, with no
// returns. Pulse 0 fires at job.options.start (INS GPS time). Each window notes the messages
// its poses came from; the first data packet sent after it times them (docs/live-navigation.md).
class LiveSession {
  public:
    LiveSession(Job& job, output::PacketOutput& out, navio::NavInput& nav,
                const navpose::PoseBuffer& poses, LiveOptions options);
    LiveSession(const LiveSession&) = delete;
    LiveSession& operator=(const LiveSession&) = delete;

    // The packetizer's sink: sends the packet and counts it; a data packet times the messages
    // of the windows rendered since the last one (a packet holds the pulses of those windows).
    void on_packet(const wire::PacketView& p);
    // Renders windows of `pulses_per_window` pulses into `packetizer` until the duration is over
    // or `stop` is set; messages applied before the call are the backlog, not timed.
    LiveTotals run(wire::Packetizer& packetizer, std::size_t pulses_per_window,
                   const std::atomic<bool>& stop);
    // Stale periods so far, from any thread.
    std::uint64_t stale_periods() const { return stale_periods_.load(std::memory_order_relaxed); }

  private:
    // Hands over the position / IMU packets due before the window ending at `t_last`, before the
    // loop sleeps until `wake_ns` to render it, so they leave on their own deadlines rather than
    // after the render (docs/live-navigation.md §1).
    void send_side_packets(wire::Packetizer& packetizer, core::GpsTime t_last,
                           std::int64_t wake_ns);
    void print_status(core::GpsTime t_last, bool stale, const std::string& stale_reason);

    Job& job_;
    output::PacketOutput& out_;
    navio::NavInput& nav_;
    const navpose::PoseBuffer& poses_;
    LiveOptions opt_;
    LiveTotals tot_;
    std::atomic<std::uint64_t> stale_periods_{0};
    navio::MessageLatency latency_;
    std::int64_t next_status_ns_ = 0;
    std::uint64_t packets_at_status_ = 0, bytes_at_status_ = 0, nav_at_status_ = 0;
};

// Streams `job`'s packets without returns on the host's clock until the first full pose, the
// duration or `stop` — as a unit spins before GPS lock; `out` is anchored here and left open.
LiveTotals stream_before_first_pose(Job& job, output::PacketOutput& out, navio::NavInput& nav,
                                    const navpose::PoseBuffer& poses, LiveOptions lo,
                                    const wire::WireOptions& wo, const std::string& to,
                                    core::Nanos delay, const std::atomic<bool>& stop);

}  // namespace mirage::hil
