// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>

#include "mirage/core/trajectory.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navproto/nav_log.hpp"
#include "mirage/navproto/protocol.hpp"

namespace mirage::bytestream {
class ByteStream;
}
namespace mirage::can {
class CanBus;
}

namespace mirage::navio {

// Faults to inject, for testing what a receiver rejects (times after t0; 0 / negative = off).
struct FakeInsFaults {
    core::Nanos silence_at{-1}, silence_for{0};  // no messages in [at, at + for)
    core::Nanos jump_at{-1};                     // one epoch's position 100 m off
    core::Nanos backwards_at{-1};                // one epoch stamped 1 s in the past
    core::Nanos nan_at{-1};           // one epoch with a NaN latitude (encoders print/pack it)
    std::uint64_t corrupt_every = 0;  // byte protocols: flip one byte of every n-th message
};

struct FakeInsConfig {
    navproto::NavProtocol protocol = navproto::NavProtocol::Nmea;
    double rate_hz = 100.0;
    core::Nanos duration{0};  // 0: the trajectory's span (held at its end pose afterwards: forever
                              // for a static pose) — until stopped
    FakeInsFaults faults;
};

struct FakeInsTotals {
    std::uint64_t epochs = 0, messages = 0, bytes = 0, write_failures = 0;
    std::uint64_t skipped = 0;  // epochs dropped because the output had blocked past them
    std::uint64_t silenced = 0, jumps = 0, backwards = 0, nans = 0, corrupted = 0;
};

// A perfect INS following a scripted trajectory in real time: at each epoch, the pose at
// trajectory time begin() + (t − t0) becomes the protocol's messages, stamped with GPS time t
// and written when the host clock (CLOCK_REALTIME, as GPS via the leap-second table) reaches t.
class FakeIns {
  public:
    FakeIns(const core::Trajectory& trajectory, navpose::NavFrame frame, FakeInsConfig config);
    // Exactly one of `stream` / `bus`. Returns when the duration is over or `stop` is set.
    FakeInsTotals run(bytestream::ByteStream* stream, can::CanBus* bus, core::GpsTime t0,
                      const std::atomic<bool>& stop);
    // The sample sent at GPS time t (for tests: the truth).
    nav::NavSample sample_at(core::GpsTime t, core::GpsTime t0) const;

  private:
    const core::Trajectory& traj_;
    navpose::NavFrame frame_;
    FakeInsConfig cfg_;
};

// GPS time now from the host's CLOCK_REALTIME, rounded down to whole milliseconds.
core::GpsTime gps_now_ms();
// The fake INS's first epoch: `lead` from now, on a whole multiple of the epoch period, so that
// protocols with coarse time fields (NMEA hhmmss.ss) carry every epoch's time exactly.
core::GpsTime fake_ins_start(double rate_hz, core::Nanos lead);

struct ReplayTotals {
    std::uint64_t messages = 0, bytes = 0, write_failures = 0;
    std::int64_t span_ns = 0;        // log time from the first to the last message sent
    std::int64_t worst_late_ns = 0;  // how far past its deadline a write started, at worst
    bool interrupted = false;
};

// Replays a recorded log with its own timing: message i is written when CLOCK_MONOTONIC reaches
// start_ns + (t_i − t_0) / speed (absolute deadlines, so delays never accumulate). Byte logs go
// to `stream` (t = the messages' own times: NMEA UTC fields, NovAtel header GPS time, NCOM
// time), CAN logs to `bus` (t = the candump timestamps). Times that run backwards in the log are
// sent at once. start_ns 0: now.
ReplayTotals replay_nav_log(const navproto::NavLog& log, bytestream::ByteStream* stream,
                            can::CanBus* bus, double speed, const std::atomic<bool>& stop,
                            std::int64_t start_ns = 0);

}  // namespace mirage::navio
