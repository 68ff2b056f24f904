// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/fake_ins.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/core/pose.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::navio {

core::GpsTime gps_now_ms() {
    const std::int64_t unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     std::chrono::system_clock::now().time_since_epoch())
                                     .count();
    return core::gps_from_unix_ns(unix_ns / 1'000'000 * 1'000'000);
}

core::GpsTime fake_ins_start(double rate_hz, core::Nanos lead) {
    const std::int64_t period = std::max<std::int64_t>(1, std::llround(1e9 / rate_hz));
    const std::int64_t t = (gps_now_ms() + lead).time_since_epoch().count();
    return core::GpsTime(core::Nanos((t + period - 1) / period * period));
}

FakeIns::FakeIns(const core::Trajectory& trajectory, navpose::NavFrame frame, FakeInsConfig config)
    : traj_(trajectory), frame_(frame), cfg_(config) {}

nav::NavSample FakeIns::sample_at(core::GpsTime t, core::GpsTime t0) const {
    const core::GpsTime tt = traj_.begin() + (t - t0);
    const core::Pose p = traj_.at(tt);
    // Velocity by a central difference over ±5 ms (the trajectory has no velocity of its own).
    const core::Nanos h(5'000'000);
    const Eigen::Vector3d v = (traj_.at(tt + h).position - traj_.at(tt - h).position) / 0.01;
    nav::NavSample s = frame_.sample(p, v);
    // Body rates by a central difference of the NED attitude over the same ±5 ms.
    const auto attitude = [&](core::GpsTime at) {
        const nav::NavSample a = frame_.sample(traj_.at(at), v);
        return core::quaternion_from_rpy(a.roll_rad, a.pitch_rad, a.heading_rad);
    };
    const Eigen::AngleAxisd turn(attitude(tt - h).conjugate() * attitude(tt + h));
    s.rate_frd_radps = turn.axis() * (turn.angle() / 0.01);
    s.t = t;
    s.fields |= nav::NavSample::kTime | nav::NavSample::kAngularRate;
    s.quality = nav::FixQuality::RtkFixed;
    s.satellites = 14;
    return s;
}

FakeInsTotals FakeIns::run(bytestream::ByteStream* stream, can::CanBus* bus, core::GpsTime t0,
                           const std::atomic<bool>& stop) {
    FakeInsTotals tot;
    auto encoder = navproto::make_nav_encoder(cfg_.protocol, cfg_.rate_hz);
    const std::int64_t period_ns = static_cast<std::int64_t>(1e9 / cfg_.rate_hz + 0.5);
    for (std::uint64_t i = 0; !stop.load(); ++i) {
        const core::GpsTime t = t0 + core::Nanos(static_cast<std::int64_t>(i) * period_ns);
        if (cfg_.duration.count() > 0 && t - t0 > cfg_.duration) break;
        const std::int64_t unix_ns = core::unix_ns_from_gps(t);
        hostclock::sleep_until_realtime(unix_ns);
        // A blocked writer (a pty nobody reads fills up) must not stretch the schedule: epochs
        // already 100 ms past are skipped, as an INS does not queue old solutions.
        if (hostclock::realtime_ns() > unix_ns + 100'000'000) {
            ++tot.skipped;
            continue;
        }
        const FakeInsFaults& f = cfg_.faults;
        const core::Nanos since = t - t0;
        if (f.silence_for.count() > 0 && since >= f.silence_at &&
            since < f.silence_at + f.silence_for) {
            ++tot.silenced;
            continue;
        }
        nav::NavSample s = sample_at(t, t0);
        const auto hits = [&](core::Nanos at) {
            return at.count() >= 0 && since >= at && since - at < core::Nanos(period_ns);
        };
        if (hits(f.jump_at)) {
            s.lat_deg += 100.0 / 111'000.0;  // ~100 m north
            ++tot.jumps;
        }
        if (hits(f.backwards_at)) {
            s.t -= std::chrono::seconds(1);
            ++tot.backwards;
        }
        if (hits(f.nan_at)) {
            s.lat_deg = std::numeric_limits<double>::quiet_NaN();
            ++tot.nans;
        }
        if (stream) {
            auto bytes = encoder->encode_bytes(s, i);
            if (f.corrupt_every > 0 && (i + 1) % f.corrupt_every == 0 && bytes.size() > 8) {
                bytes[bytes.size() / 2] ^= 0x5A;  // inside the payload: a checksum/CRC mismatch
                ++tot.corrupted;
            }
            if (!stream->write(bytes)) ++tot.write_failures;
            tot.bytes += bytes.size();
            ++tot.messages;
        } else if (bus) {
            for (const auto& f : encoder->encode_frames(s, i)) {
                if (!bus->send(f)) ++tot.write_failures;
                ++tot.messages;
                tot.bytes += f.len;
            }
        }
        ++tot.epochs;
    }
    return tot;
}

}  // namespace mirage::navio

namespace mirage::navio {
namespace {}  // namespace

ReplayTotals replay_nav_log(const navproto::NavLog& log, bytestream::ByteStream* stream,
                            can::CanBus* bus, double speed, const std::atomic<bool>& stop,
                            std::int64_t start_ns) {
    ReplayTotals tot;
    if (!(speed > 0)) speed = 1.0;
    if (start_ns == 0) start_ns = hostclock::monotonic_ns();
    const bool frames = navproto::is_can(log.protocol);
    const std::size_t n = frames ? log.frames.size() : log.messages.size();
    const auto time_of = [&](std::size_t i) -> std::int64_t {
        return frames ? log.frames[i].stamped.time_ns
                      : log.messages[i].t.time_since_epoch().count();
    };
    if (n == 0) return tot;
    const std::int64_t t0 = time_of(0);
    std::int64_t last = start_ns;
    for (std::size_t i = 0; i < n; ++i) {
        if (stop.load()) {
            tot.interrupted = true;
            break;
        }
        const std::int64_t rel = time_of(i) - t0;
        // Deadlines never go back: a time glitch in the log is sent at once, not reordered.
        const std::int64_t due =
            std::max(last, start_ns + static_cast<std::int64_t>(std::llround(double(rel) / speed)));
        last = due;
        hostclock::sleep_until_monotonic(due);
        tot.worst_late_ns = std::max(tot.worst_late_ns, hostclock::monotonic_ns() - due);
        if (frames) {
            const nav::CanFrame& f = log.frames[i].stamped.frame;
            if (!bus || !bus->send(f)) ++tot.write_failures;
            tot.bytes += f.len;
        } else {
            const navproto::NavLogMessage& m = log.messages[i];
            const std::span<const std::uint8_t> b(log.bytes.data() + m.offset, m.size);
            if (!stream || !stream->write(b)) ++tot.write_failures;
            tot.bytes += m.size;
        }
        ++tot.messages;
        tot.span_ns = rel;
    }
    return tot;
}

}  // namespace mirage::navio
