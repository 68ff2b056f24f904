// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "mirage/can/can_bus.hpp"
#include "mirage/nav/lower_envelope.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navpose/nav_mapper.hpp"
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
    navpose::NavMapperConfig mapper;  // --undulation, --max-jump-m
    // NMEA: the UTC date assumed until an RMC/ZDA gives one. "host": today's (a live INS);
    // "stream": none, sentences before the stream's first date are dropped (a recorded log of
    // another day: a host-date guess would put its first sentences years ahead of the rest);
    // or "YYYY-MM-DD".
    std::string nmea_date = "host";
    PoseLog* pose_log = nullptr;    // every applied track update, written by the nav thread
    NavRecorder* record = nullptr;  // the raw input as it arrived
};

struct NavInputCounters {
    nav::DecodeCounters decode;  // the decoder's: checksums, truncated frames, bad fields
    navpose::NavCounters track;  // the mapper's: what was applied and what the rules refused
    std::uint64_t transport_closed = 0;
    std::uint64_t error_frames = 0;  // CAN
    std::string detail;              // the protocol's own counters (DIS), refreshed every second
};

// A message that updated the pose buffer, for the INS-to-packet latency: its tag and tracks.
struct AppliedMessage {
    navpose::MessageTag tag;
    bool position = false, attitude = false;
};

// Reads one navigation source on its own thread: transport -> decoder -> navpose::NavMapper
// (scene frame and rejection rules) -> pose buffer. Every decoded sample is numbered and
// stamped with its arrival (MessageTag). Tracks the offset between INS time and the host's
// CLOCK_MONOTONIC as the lower envelope of (arrival − INS time) (docs/nav-protocols.md §12.3
// item 3).
class NavInput {
  public:
    // Throws ConfigError / IoError when the transport won't open. The recorders must outlive
    // stop(); the caller closes them after stop().
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
    // The local UDP port a udp:// transport bound (0 otherwise): `udp://127.0.0.1:0` picks one.
    std::uint16_t udp_port() const;
    // Messages applied since the last call, oldest first. A message is listed here before its
    // samples reach the pose buffer, so a window that used it finds it.
    std::vector<AppliedMessage> take_applied();
    // The CAN bus's counters (nullopt for byte transports).
    std::optional<can::BusCounters> bus_counters() const;

  private:
    void run();
    void on_sample(const nav::NavSample& s, std::int64_t host_ns);
    void track_offset(const nav::NavSample& s, std::int64_t host_ns);

    navproto::NavUri uri_;
    navpose::PoseBuffer& poses_;
    navpose::NavMapper mapper_;  // nav thread only
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
    nav::LowerEnvelope offset_{10'000'000'000};  // over 10-20 s
    std::vector<AppliedMessage> applied_;
};

}  // namespace mirage::navio
