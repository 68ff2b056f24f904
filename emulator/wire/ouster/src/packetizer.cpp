// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/packetizer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mirage/core/rounding.hpp"

namespace mirage::ouster {

OusterPacketizer::OusterPacketizer(Descriptor d, PacketizerConfig cfg, wire::PacketFn sink)
    : d_(std::move(d)),
      cfg_(std::move(cfg)),
      sink_(std::move(sink)),
      pulses_per_packet_(std::uint64_t{d_.columns_per_packet} * d_.beams),
      bytes_(d_.packet_bytes()) {
    packet_.resize(d_);
    best_.assign(packet_.pixels.size(), -1.0);
    range_add_mm_.assign(d_.beams, 0.0);
    constexpr double kDeg = std::numbers::pi / 180.0;
    for (std::size_t r = 0; r < d_.beams && r < d_.altitude_deg.size(); ++r) {
        const double az = r < d_.azimuth_deg.size() ? d_.azimuth_deg[r] : 0.0;
        range_add_mm_[r] =
            d_.beam_origin_mm * (1.0 - std::cos(d_.altitude_deg[r] * kDeg) * std::cos(az * kDeg));
    }
    covered_ = cfg_.start;
    reset_buffer();
}

core::GpsTime OusterPacketizer::column_time(std::uint64_t column) const {
    // Same rounding as SpinningPattern::pulses (llround of s·period).
    return cfg_.start +
           core::Nanos(std::llround(static_cast<double>(column) * d_.column_period_ns()));
}

std::uint16_t OusterPacketizer::measurement_id(std::uint64_t column) const {
    return static_cast<std::uint16_t>(column % d_.mode.columns);
}

std::uint16_t OusterPacketizer::frame_id(std::uint64_t column) const {
    return static_cast<std::uint16_t>(cfg_.first_frame_id + column / d_.mode.columns);
}

void OusterPacketizer::reset_buffer() {
    std::fill(packet_.pixels.begin(), packet_.pixels.end(), Pixel{});
    std::fill(best_.begin(), best_.end(), -1.0);
}

void OusterPacketizer::add(std::span<const core::PointRecord> points) {
    const std::size_t H = d_.beams;
    const double max_mm = d_.profile == Profile::Legacy          ? double((1u << 20) - 1)
                          : d_.profile == Profile::Rng15Rfl8Nir8 ? double(((1u << 15) - 1) * 8)
                                                                 : double((1u << 19) - 1);
    for (const auto& p : points) {
        const std::uint64_t packet = p.pulse / pulses_per_packet_;
        if (packet < current_) {
            ++stats_.out_of_order;
            continue;
        }
        // Points arrive in pulse order: a later packet's point completes the earlier ones.
        if (packet > current_) emit_through(packet);
        const std::size_t slot = static_cast<std::size_t>(p.pulse % pulses_per_packet_);
        const std::size_t col = slot / H, row = slot % H;
        const std::size_t i = col * H + row;
        if (best_[i] >= 0) {
            ++stats_.extra_returns;
            if (p.n_laser <= best_[i]) continue;  // keep the strongest (single-return profiles)
        }
        const double mm = double(p.range_m) * 1000.0 + range_add_mm_[row];
        if (!(mm >= 0.5) || mm > max_mm) {
            ++stats_.out_of_range;
            continue;
        }
        if (best_[i] < 0) ++stats_.returns;
        best_[i] = std::max(p.n_laser, 0.0);
        Pixel& px = packet_.pixels[i];
        // Round once to the field's unit (RNG15: 8 mm), so the error stays within half of it.
        px.range_mm = d_.profile == Profile::Rng15Rfl8Nir8
                          ? static_cast<std::uint32_t>(8 * core::round_half_away(mm / 8.0))
                          : static_cast<std::uint32_t>(core::round_half_away(mm));
        px.reflectivity = static_cast<std::uint16_t>(p.intensity >> 8);
        px.signal =
            static_cast<std::uint16_t>(std::clamp(core::round_half_away(p.n_laser), 0.0, 65535.0));
        px.nir = cfg_.nir;
        px.flags = 0;
    }
}

void OusterPacketizer::advance_to(std::uint64_t next_pulse) {
    emit_through(next_pulse / pulses_per_packet_);
    const core::GpsTime t = column_time(next_pulse / d_.beams);
    if (t > covered_) covered_ = t;
    emit_imu_until(covered_);
}

void OusterPacketizer::emit_side_packets_until(core::GpsTime t) {
    // Not past the send time of the packet being filled (its last column's end).
    emit_imu_until(std::min(t, column_time((current_ + 1) * d_.columns_per_packet)));
}

void OusterPacketizer::finish() { emit_imu_until(covered_); }

void OusterPacketizer::emit_through(std::uint64_t packet_end) {
    while (current_ < packet_end) {
        emit_current();
        ++current_;
        reset_buffer();
    }
}

void OusterPacketizer::emit_current() {
    const std::uint64_t first_col = current_ * d_.columns_per_packet;
    const core::GpsTime send = column_time(first_col + d_.columns_per_packet);
    emit_imu_until(send);
    if (send > covered_) covered_ = send;

    packet_.header.packet_type = kPacketTypeLidar;
    packet_.header.frame_id = frame_id(first_col);
    packet_.header.init_id = d_.init_id;
    packet_.header.serial = d_.serial;
    packet_.header.thermal_shutdown_countdown = d_.thermal_shutdown_countdown;
    packet_.header.shot_limiting_countdown = d_.shot_limiting_countdown;
    packet_.header.thermal_shutdown_status = d_.thermal_shutdown_status;
    packet_.header.shot_limiting_status = d_.shot_limiting_status;
    const std::int64_t step = cfg_.clock.step_now();  // one per packet
    for (std::size_t c = 0; c < d_.columns_per_packet; ++c) {
        const std::uint64_t s = first_col + c;
        ColumnHeader& h = packet_.columns[c];
        h.timestamp_ns = cfg_.clock.ns(column_time(s), step);
        h.measurement_id = measurement_id(s);
        h.frame_id = frame_id(s);
        h.encoder_count = d_.encoder_count(h.measurement_id);
        h.status = valid_column_status(d_);
    }
    encode_lidar_packet(d_, packet_, bytes_);
    ++stats_.lidar_packets;
    if (sink_) sink_(wire::PacketView{wire::Stream::Data, send, bytes_});
}

void OusterPacketizer::emit_imu_until(core::GpsTime t) {
    if (!cfg_.imu || cfg_.imu_period.count() <= 0) return;
    std::array<std::uint8_t, kImuPacketBytes> buf{};
    for (;;) {
        const core::GpsTime ti =
            cfg_.start + cfg_.imu_period * static_cast<std::int64_t>(next_imu_);
        if (ti > t) break;
        const ImuReading r = cfg_.imu(ti);
        ImuPacket p;
        const std::int64_t step = cfg_.clock.step_now();  // one per packet
        p.sys_ns = cfg_.clock.ns(ti, step);
        p.accel_ns = cfg_.clock.ns(ti + cfg_.imu_accel_delay, step);
        p.gyro_ns = cfg_.clock.ns(ti + cfg_.imu_gyro_delay, step);
        for (int k = 0; k < 3; ++k) {
            p.accel_g[static_cast<std::size_t>(k)] = static_cast<float>(r.accel_g[k]);
            p.gyro_dps[static_cast<std::size_t>(k)] = static_cast<float>(r.gyro_dps[k]);
        }
        encode_imu_packet(p, buf);
        ++stats_.imu_packets;
        ++next_imu_;
        if (sink_) sink_(wire::PacketView{wire::Stream::Imu, ti, buf});
    }
}

}  // namespace mirage::ouster
