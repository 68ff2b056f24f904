// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "mirage/hostclock/clock_step.hpp"
#include "mirage/pcap/writer.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/shared_sender.hpp"
#include "mirage/udp/udp_sender.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::output {

struct PacketOutputOptions {
    std::optional<udp::SenderConfig> udp;               // none: no network output
    std::string pcap_path;                              // empty: no capture file
    pcap::Endpoint pcap_source{{192, 168, 1, 201}, 0};  // the emulated device's address
    udp::StreamPorts pcap_source_ports{2368, 8308, 7503};
    udp::StreamPorts pcap_dest_ports{2368, 8308, 7503};  // the UDP config's ports when sending
    bool realtime = true;  // pace on the sensor clock; false: as fast as possible
    bool status_line = true;
    // > 0: the thread that sends (the render's writer thread) switches to SCHED_FIFO at this
    // priority on its first packet, so a busy core cannot delay its wake-ups; render workers,
    // created before, keep the normal policy. (The spin before each deadline stays at the
    // Pacer's 50 µs: on virtual machines timer wake-ups are late by tens of µs even for FIFO
    // threads; docs/benchmarks.md §2.)
    int fifo_priority = 0;
    // >= 0: the sending thread (the shared sender's, or the writer thread that paces) runs on
    // this CPU, the one --keep-awake keeps out of idle (docs/time.md §5). The shared sender
    // takes it from its own config.
    int pin_cpu = -1;
    // Realtime UDP output through one deadline-ordered sending thread (udp::SharedSender) instead
    // of pacing in the calling thread: the caller then only waits while it is more than the
    // sender's horizon ahead, and stays SCHED_OTHER. The thread is shared among the outputs it
    // is given to (its own config sets FIFO); stream-bench gives one to its three streams.
    // Ignored without `udp` or `realtime` (a capture alone is paced by the caller as before).
    std::shared_ptr<udp::SharedSender> shared_sender;
    // Realtime: the first packet is due this long after it is produced, so the renderers build
    // a lead before sending starts (a start-up with three streams briefly renders slower than
    // real time). Unless anchor() was called. 0 for INS-driven output, where it would be latency.
    core::Nanos start_lead{0};
    // A sensor clock anchored to the host's GPS time: each packet polls for host clock steps,
    // which the encoder adds to the timestamps from its next packet on, and the capture to its
    // record times (docs/time.md §1). May be shared by the outputs of one rig.
    hostclock::ClockStepFollower* clock_follower = nullptr;
};

// `mirage emulate`'s start lead (stream-bench uses the same): three streams starting at once
// render slower than real time for their first tens of milliseconds (recordings/bench/streams.md).
inline constexpr core::Nanos kEmulateStartLead{100'000'000};
// How far `mirage emulate`'s renderers may run ahead of the packet schedule (render::
// RenderOptions::window_chunks; set_render_lead in job.hpp). Trajectory-driven output knows its
// poses in advance, so a lead costs only memory (tens of MB for OS1-128 2048×10) and rides out
// the tens of milliseconds a loaded 2-core machine can stall one stream's workers. The default
// window (2 chunks per thread + 2) is only 19–57 ms of OS1-128 firing.
inline constexpr core::Nanos kEmulateRenderLead{300'000'000};

struct PacketOutputTotals {
    std::uint64_t packets = 0, bytes = 0, sent = 0, send_failed = 0, pcap_packets = 0;
    std::uint64_t discarded = 0;  // queued, then dropped unsent (discard_queued)
    std::uint64_t late = 0;       // later than the pacer's threshold
    std::uint64_t paced = 0;      // packets whose lateness was measured (realtime)
    std::uint64_t from_50us = 0;  // of those, 50 µs late or more (docs/benchmarks.md §3.1)
    core::Nanos worst_late{0}, p50{0}, p99{0};
    core::Nanos send_p50{0}, send_p99{0};  // duration of the send calls (shared sender only)
    double seconds = 0;                    // host time from the first packet to the last
    bool fifo = false;                     // the sending thread ran SCHED_FIFO
    std::string fifo_error;                // why not, when it was asked for
};

// "50 µs late or more P % of N": the share of paced packets held against the machine's floor
// (docs/benchmarks.md §3.1); empty when nothing was paced.
std::string late_share_text(const PacketOutputTotals& t);

// A sensor's UDP streams: data on `data` or the vendor's port (2368 Velodyne, 7502 Ouster),
// Velodyne position / Ouster IMU on theirs (0 = off); the family's other stream is off.
udp::StreamPorts sensor_ports(bool ouster, std::uint16_t data, std::uint16_t position,
                              std::uint16_t imu);
// Sends those streams to `host` (none when empty; data from `source_port` when non-zero) and
// labels the pcap's packets with the same ports.
void route_streams(PacketOutputOptions& po, const udp::StreamPorts& ports, const std::string& host,
                   std::uint16_t source_port = 0);

// Where packets go: paced by absolute deadlines on the sensor clock, sent over UDP, written to a
// pcap with their sensor-clock send times, and summarised in a status line once a second.
class PacketOutput {
  public:
    explicit PacketOutput(PacketOutputOptions options);  // throws ConfigError / IoError
    void operator()(const wire::PacketView& packet);     // never throws on send errors
    // Ties sensor time t0 to host CLOCK_MONOTONIC host_ns before the first packet (default: the
    // first packet's time is "now"); for measuring lateness against the same schedule.
    void anchor(core::GpsTime t0, std::int64_t host_monotonic_ns) {
        pacer_.anchor(t0, host_monotonic_ns);
    }
    // Packets go to a deadline-ordered sending thread (a shared sender): operator() hands a
    // packet over ahead of its send time instead of waiting for it.
    bool hands_over_ahead() const { return shared_ != nullptr; }
    // CLOCK_MONOTONIC ns at which a packet of sensor time `t` is due (realtime, once anchored).
    std::int64_t deadline_ns(core::GpsTime t) const { return pacer_.deadline_ns(t); }
    // Flushes and closes the pcap and ends the status line. Throws IoError (naming the file) if
    // writing the capture failed at any point; the stream itself never stops for it.
    PacketOutputTotals finish();
    const PacketOutputOptions& options() const { return opt_; }
    // Through a shared sender: drops the packets queued and not yet sent (a stopped sensor goes
    // quiet at once instead of after its render lead); any thread. Returns how many.
    std::uint64_t discard_queued() { return shared_ ? shared_->sender->discard(shared_->id) : 0; }
    // Through a shared sender: its channel's counters so far, from any thread (a rig's control
    // plane reads them while streaming); nullopt otherwise.
    std::optional<udp::ChannelCounters> channel_counters() const {
        if (!shared_) return std::nullopt;
        return shared_->sender->counters(shared_->id);
    }

  private:
    void tick(std::chrono::steady_clock::time_point now);
    void print_status(bool final);
    void start_shared();

    // This output's queue in a SharedSender; closing it (destruction) waits for its packets, so
    // it is declared after, and destroyed before, the UdpSender it sends through.
    struct SharedChannel {
        std::shared_ptr<udp::SharedSender> sender;
        udp::SharedSender::ChannelId id = 0;
        SharedChannel(std::shared_ptr<udp::SharedSender> s, udp::SharedSender::ChannelId i)
            : sender(std::move(s)), id(i) {}
        SharedChannel(const SharedChannel&) = delete;
        SharedChannel& operator=(const SharedChannel&) = delete;
        ~SharedChannel() {
            if (sender) sender->close(id);
        }
    };

    PacketOutputOptions opt_;
    std::unique_ptr<udp::UdpSender> sender_;
    std::unique_ptr<SharedChannel> shared_;  // null: paced by pacer_ in the calling thread
    std::unique_ptr<pcap::Writer> pcap_;
    pcap::Endpoint pcap_dst_;
    udp::StreamPorts pcap_dst_ports_;
    udp::Pacer pacer_;
    PacketOutputTotals totals_;
    std::chrono::steady_clock::time_point first_{}, last_status_{};
    std::uint64_t packets_at_status_ = 0, bytes_at_status_ = 0;
    bool started_ = false, status_printed_ = false;
    std::chrono::steady_clock::time_point last_tick_{};
    std::string pcap_error_;  // the capture's write error; finish() throws it
};

}  // namespace mirage::output
