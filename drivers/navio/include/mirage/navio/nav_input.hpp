// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "mirage/can/can_bus.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navpose/pose_buffer.hpp"
#include "mirage/navproto/protocol.hpp"

namespace mirage::bytestream {
class ByteStream;
}
namespace mirage::navio {

class PoseLog;
class NavRecorder;

// What NavInput does besides decoding and applying (all optional).
struct NavInputOptions {
    double undulation_m = 0;  // added to heights an INS reports above MSL
    // NMEA: the UTC date assumed until an RMC/ZDA gives one. "host": today's (a live INS);
    // "stream": none, sentences before the stream's first date are dropped (a recorded log of
    // another day: a host-date guess would put its first sentences years ahead of the rest);
    // or "YYYY-MM-DD".
    std::string nmea_date = "host";
    PoseLog* pose_log = nullptr;    // every applied track update, written by the nav thread
    NavRecorder* record = nullptr;  // the raw input as it arrived
};

struct NavInputCounters {
    std::uint64_t samples = 0;          // NavSamples decoded
    std::uint64_t applied = 0;          // samples that updated the pose buffer
    std::uint64_t decode_rejected = 0;  // bad checksums, truncated frames, bad fields
    std::uint64_t pose_rejected = 0;    // NaN, time backwards, position jumps
    std::uint64_t no_time = 0;          // samples without a full time (e.g. NMEA before a date)
    std::uint64_t transport_closed = 0;
    std::uint64_t error_frames = 0;  // CAN
};

// Reads one navigation source on its own thread: transport -> decoder -> scene frame -> pose
// buffer. Tracks the offset between INS time and the host's CLOCK_MONOTONIC as the lower
// envelope of (arrival − INS time) (nav-protocols.md §12.3 item 3), and records arrival times
// for the INS-to-packet latency figure.
class NavInput {
  public:
    NavInput(const navproto::NavUri& uri, navpose::NavFrame frame, navpose::PoseBuffer& poses,
             double undulation_m);  // throws ConfigError / IoError when the transport won't open
    // Same, with recording and NMEA date options. The recorders must outlive stop(); the
    // caller closes them after stop().
    NavInput(const navproto::NavUri& uri, navpose::NavFrame frame, navpose::PoseBuffer& poses,
             const NavInputOptions& options);
    ~NavInput();
    NavInput(const NavInput&) = delete;
    NavInput& operator=(const NavInput&) = delete;

    void start();
    void stop();

    // host CLOCK_MONOTONIC ns − INS GPS ns (lower envelope); nullopt before the first sample.
    std::optional<std::int64_t> offset_ns() const;
    NavInputCounters counters() const;
    nav::DecodeCounters decode_counters() const;
    // The local UDP port a udp:// transport bound (0 otherwise): `udp://127.0.0.1:0` picks one.
    std::uint16_t udp_port() const;
    // Arrival times (host monotonic ns) of applied samples not yet taken, oldest first.
    std::deque<std::int64_t> take_arrivals();
    // The CAN bus's counters (nullopt for byte transports).
    std::optional<can::BusCounters> bus_counters() const;

  private:
    void run();
    void on_sample(const nav::NavSample& s, std::int64_t host_ns);

    navproto::NavUri uri_;
    navpose::NavFrame frame_;
    navpose::PoseBuffer& poses_;
    double undulation_m_;
    PoseLog* pose_log_ = nullptr;
    NavRecorder* record_ = nullptr;
    std::unique_ptr<navproto::NavDecoder> decoder_;
    std::unique_ptr<bytestream::ByteStream> stream_;
    std::unique_ptr<can::CanBus> bus_;
    bool datagrams_ = false;
    std::atomic<bool> stop_{false};
    std::thread thread_;
    mutable std::mutex mu_;
    NavInputCounters counters_;
    nav::DecodeCounters decode_counters_;
    std::optional<std::int64_t> offset_;
    std::int64_t offset_block_min_ = 0;
    std::int64_t prev_block_min_ = 0;
    double last_lat_ = 0, last_lon_ = 0;  // for the convergence of attitude-only messages
    bool have_latlon_ = false;
    std::int64_t offset_block_start_ = 0;
    std::deque<std::int64_t> arrivals_;
};

}  // namespace mirage::navio
