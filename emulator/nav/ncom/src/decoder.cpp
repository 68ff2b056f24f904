// SPDX-License-Identifier: Apache-2.0
#include "mirage/ncom/decoder.hpp"

#include <cmath>
#include <numbers>

#include "mirage/ncom/encoder.hpp"

namespace mirage::ncom {
namespace {

using nav::NavSample;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kPi = std::numbers::pi;
constexpr double kMinAltM = -10'000.0;
constexpr double kMaxAltM = 100'000.0;
constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kNsPerMinute = 60 * core::kNsPerSecond;
// Channel-0 minutes beyond ~190 years after 1980 are corrupt (and would overflow int64 ns).
constexpr std::int32_t kMaxGpsMinutes = 100'000'000;

bool any_invalid(const std::array<std::int32_t, 3>& v) {
    return v[0] == kInvalidI24 || v[1] == kInvalidI24 || v[2] == kInvalidI24;
}

Eigen::Vector3d scaled(const std::array<std::int32_t, 3>& v, double scale) {
    return {v[0] * scale, v[1] * scale, v[2] * scale};
}

bool is_regular_status(std::uint8_t s) { return s <= kNavExpired; }

}  // namespace

void NcomDecoder::feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample) {
    buf_.append(bytes);
    buf_.drain(
        counters_.garbage_bytes,
        [](std::uint8_t b) { return b == kSync ? nav::ByteKind::Sync : nav::ByteKind::Garbage; },
        [](std::span<const std::uint8_t> rest) {
            return rest.size() < kPacketSize ? nav::FrameLength::need_more()
                                             : nav::FrameLength::complete(kPacketSize);
        },
        [&](std::span<const std::uint8_t> frame) -> std::size_t {
            const std::span<const std::uint8_t, kPacketSize> pkt(frame.data(), kPacketSize);
            // In sync: this candidate starts where the last good packet ended.
            const bool in_sync = buf_.offset() == good_end_;
            if (!checksums_ok(pkt)) {
                if (in_sync)
                    ++counters_.bad_checksum;
                else
                    ++counters_.garbage_bytes;
                return 1;
            }
            handle_packet(pkt, on_sample);
            good_end_ = buf_.offset() + kPacketSize;
            return kPacketSize;
        });
}

void NcomDecoder::feed_datagram(std::span<const std::uint8_t> datagram,
                                const nav::SampleFn& on_sample) {
    std::size_t off = 0;
    for (; off + kPacketSize <= datagram.size(); off += kPacketSize) {
        const std::span<const std::uint8_t, kPacketSize> pkt(datagram.data() + off, kPacketSize);
        if (pkt[0] != kSync) {
            counters_.garbage_bytes += kPacketSize;
            continue;
        }
        if (!checksums_ok(pkt)) {
            ++counters_.bad_checksum;
            continue;
        }
        handle_packet(pkt, on_sample);
    }
    if (off < datagram.size()) ++counters_.truncated;
}

void NcomDecoder::handle_packet(std::span<const std::uint8_t, kPacketSize> bytes,
                                const nav::SampleFn& on_sample) {
    const Packet p = unpack(bytes);
    if (!is_regular_status(p.nav_status)) {
        // Status-only (10) and trigger packets (20-22) time other events; not decoded.
        ++counters_.unsupported;
        return;
    }
    if (p.ms_of_minute >= kMsPerMinute) {
        ++counters_.invalid_field;
        return;
    }
    const Channel0 c0 = unpack_channel0(p.status);
    if (p.channel == 0 && (c0.gps_minutes < 0 || c0.gps_minutes > kMaxGpsMinutes)) {
        ++counters_.invalid_field;
        return;
    }
    // Time state: carry the minute forward across the ms wrap, take channel 0 as truth.
    const std::int32_t ms = p.ms_of_minute;
    if (have_minutes_ && ms < last_ms_) ++minutes_;
    last_ms_ = ms;
    if (p.channel == 0) {
        channel0_ = c0;
        minutes_ = c0.gps_minutes;
        have_minutes_ = true;
    }

    if (p.nav_status != kNavLocked) {
        ++counters_.messages_ok;
        ++ncom_.not_locked;
        return;
    }
    const double alt = static_cast<double>(p.alt_m);
    if (!std::isfinite(p.lat_rad) || !std::isfinite(p.lon_rad) || std::abs(p.lat_rad) > kPi / 2 ||
        std::abs(p.lon_rad) > kPi || !std::isfinite(alt) || alt < kMinAltM || alt > kMaxAltM) {
        ++counters_.invalid_field;
        return;
    }
    const bool att_valid =
        p.heading != kInvalidI24 && p.pitch != kInvalidI24 && p.roll != kInvalidI24;
    // i24 × 1e-6 reaches ±8.4 rad: a pitch beyond ±90° or roll beyond ±180° is corrupt.
    if (att_valid && (std::abs(p.pitch * kAngleScale) > kPi / 2 + 1e-6 ||
                      std::abs(p.roll * kAngleScale) > kPi + 1e-6 ||
                      std::abs(p.heading * kAngleScale) > 2 * kPi + 1e-6)) {
        ++counters_.invalid_field;
        return;
    }
    ++counters_.messages_ok;
    if (!have_minutes_) {
        ++ncom_.no_time;
        return;
    }

    NavSample s;
    s.source = nav::Protocol::Ncom;
    s.t = core::GpsTime(core::Nanos(minutes_ * kNsPerMinute + ms * kNsPerMs));
    s.fields = NavSample::kTime | NavSample::kPosition;
    s.lat_deg = p.lat_rad * kRadToDeg;
    s.lon_deg = p.lon_rad * kRadToDeg;
    s.height_m = alt;
    if (options_.altitude_is_msl) s.fields |= NavSample::kHeightIsMsl;
    if (!any_invalid(p.vel_ned)) {
        s.velocity_ned_mps = scaled(p.vel_ned, kVelScale);
        s.fields |= NavSample::kVelocity;
    }
    if (att_valid) {
        double h = std::fmod(p.heading * kAngleScale, 2 * kPi);
        if (h < 0.0) h += 2 * kPi;
        if (h >= 2 * kPi) h = 0.0;
        s.heading_rad = h;
        s.pitch_rad = p.pitch * kAngleScale;
        s.roll_rad = p.roll * kAngleScale;
        s.fields |= NavSample::kAttitude;
    }
    if (!any_invalid(p.accel)) {
        s.accel_frd_mps2 = scaled(p.accel, kAccelScale);  // vehicle frame x fwd, y right, z down
        s.fields |= NavSample::kAcceleration;
    }
    if (!any_invalid(p.rate)) {
        s.rate_frd_radps = scaled(p.rate, kRateScale);
        s.fields |= NavSample::kAngularRate;
    }
    s.quality = quality_from_position_mode(channel0_.position_mode);
    s.satellites = channel0_.satellites;
    ++counters_.samples;
    if (on_sample) on_sample(s);
}

void NcomDecoder::finish() {
    if (buf_.size() > 0) ++counters_.truncated;
    buf_.clear();
    good_end_ = kNotInSync;
}

void NcomDecoder::reset() { *this = NcomDecoder(options_); }

}  // namespace mirage::ncom
