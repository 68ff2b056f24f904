// SPDX-License-Identifier: Apache-2.0
#include "mirage/ncom/encoder.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::ncom {
namespace {

using nav::FixQuality;
using nav::NavSample;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr std::size_t kMaxChannel0Period = 5;

// Longest run of packets between two channel-0 packets, cyclically, + 1 (the period).
std::size_t channel0_period(const std::vector<std::uint8_t>& ch) {
    std::size_t worst = 0;
    for (std::size_t i = 0; i < ch.size(); ++i) {
        if (ch[i] != 0) continue;
        std::size_t k = 1;
        while (k <= ch.size() && ch[(i + k) % ch.size()] != 0) ++k;
        if (k > worst) worst = k;
    }
    return worst;  // 0: no channel 0 at all
}

}  // namespace

std::uint8_t position_mode_for(FixQuality q) {
    switch (q) {
        case FixQuality::None:
        case FixQuality::DeadReckoning:
            return kModeNone;
        case FixQuality::Differential:
            return kModeDifferential;
        case FixQuality::RtkFloat:
            return kModeRtkFloat;
        case FixQuality::RtkFixed:
            return kModeRtkInteger;
        case FixQuality::Unknown:
        case FixQuality::Autonomous:
        case FixQuality::Simulated:
            break;
    }
    return kModeSps;
}

FixQuality quality_from_position_mode(std::uint8_t mode) {
    switch (mode) {
        case kModeNone:
        case kModeSearch:
        case kModeNoData:
        case kModeBlanked:
        case kModeNotRecognised:
            // Locked INS without a GNSS position: it is dead-reckoning.
            return FixQuality::DeadReckoning;
        case kModeDoppler:
        case kModeSps:
        case kModeDopplerPp:
        case kModeSpsPp:
        case kModeGxDoppler:
        case kModeGxSps:
            return FixQuality::Autonomous;
        case kModeDifferential:
        case kModeWaas:
        case kModeOmnistar:
        case kModeDifferentialPp:
        case kModeCdgps:
        case kModeGxDifferential:
            return FixQuality::Differential;
        case kModeRtkFloat:
        case kModeOmnistarHp:
        case kModeRtkFloatPp:
        case kModeOmnistarXp:
        case kModeGxFloat:
            return FixQuality::RtkFloat;
        case kModeRtkInteger:
        case kModeRtkIntegerPp:
        case kModeGxInteger:
            return FixQuality::RtkFixed;
        default:
            return FixQuality::Unknown;
    }
}

NcomEncoder::NcomEncoder(EncoderOptions options) : options_(std::move(options)) {
    const std::size_t period = channel0_period(options_.channels);
    if (period == 0 || period > kMaxChannel0Period)
        throw ConfigError("ncom encoder: channels: channel 0 must come at least every " +
                          std::to_string(kMaxChannel0Period) + "th packet");
}

Packet NcomEncoder::to_packet(const NavSample& s, std::uint8_t channel) const {
    Packet p;
    // Time: nearest ms, split into GPS minute + ms of minute.
    const std::int64_t ns = s.t.time_since_epoch().count();
    const std::int64_t ms_total = (ns >= 0 ? ns + 500'000 : ns - 499'999) / 1'000'000;
    std::int64_t minutes = ms_total / kMsPerMinute;
    std::int64_t ms = ms_total % kMsPerMinute;
    if (ms < 0) {
        ms += kMsPerMinute;
        --minutes;
    }
    p.ms_of_minute = static_cast<std::uint16_t>(ms);
    p.nav_status = s.quality == FixQuality::None ? kNavInitialising : kNavLocked;

    const auto vec = [](const Eigen::Vector3d& v, double scale, bool valid) {
        std::array<std::int32_t, 3> r{kInvalidI24, kInvalidI24, kInvalidI24};
        if (valid)
            for (int i = 0; i < 3; ++i) r[static_cast<std::size_t>(i)] = quantise_i24(v[i], scale);
        return r;
    };
    p.accel = vec(s.accel_frd_mps2, kAccelScale, s.has(NavSample::kAcceleration));
    p.rate = vec(s.rate_frd_radps, kRateScale, s.has(NavSample::kAngularRate));
    p.vel_ned = vec(s.velocity_ned_mps, kVelScale, s.has(NavSample::kVelocity));

    p.lat_rad = s.lat_deg * kDegToRad;
    p.lon_rad = s.lon_deg * kDegToRad;
    p.alt_m = static_cast<float>(s.height_m);
    if (s.has(NavSample::kAttitude) || s.has(NavSample::kHeading)) {
        double h = s.heading_rad;
        // OxTS reports heading in (−180°, 180°]
        if (h > std::numbers::pi) h -= 2 * std::numbers::pi;
        p.heading = quantise_i24(h, kAngleScale);
        const bool att = s.has(NavSample::kAttitude);
        p.pitch = att ? quantise_i24(s.pitch_rad, kAngleScale) : kInvalidI24;
        p.roll = att ? quantise_i24(s.roll_rad, kAngleScale) : kInvalidI24;
    } else {
        p.heading = p.pitch = p.roll = kInvalidI24;
    }

    p.channel = channel;
    if (channel == 0) {
        Channel0 c;
        c.gps_minutes = static_cast<std::int32_t>(minutes);
        c.satellites = s.satellites;
        c.position_mode = position_mode_for(s.quality);
        c.velocity_mode = c.position_mode;
        c.orientation_mode = c.position_mode;
        p.status = pack_channel0(c);
    }
    return p;
}

std::array<std::uint8_t, kPacketSize> NcomEncoder::encode(const NavSample& s) {
    const std::uint8_t channel = options_.channels[count_ % options_.channels.size()];
    ++count_;
    return pack(to_packet(s, channel));
}

}  // namespace mirage::ncom
