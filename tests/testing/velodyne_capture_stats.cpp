// SPDX-License-Identifier: Apache-2.0
#include "velodyne_capture_stats.hpp"

#include <algorithm>
#include <cstdio>

#include "mirage/velodyne/sensor_clock.hpp"

namespace mirage::velodyne {

void Summary::add(double v) {
    if (n == 0) {
        min = max = v;
    } else {
        min = std::min(min, v);
        max = std::max(max, v);
    }
    ++n;
    mean += (v - mean) / static_cast<double>(n);
}

wire::Stream stream_for_port(std::uint16_t dst_port) {
    if (dst_port == kDataPort) return wire::Stream::Data;
    if (dst_port == kPositionPort) return wire::Stream::Position;
    return wire::Stream::Imu;
}

void CaptureStatsBuilder::add(const wire::PacketView& packet) {
    add(packet.stream, packet.time.time_since_epoch().count(), packet.bytes);
}

void CaptureStatsBuilder::add(wire::Stream stream, std::int64_t time_ns,
                              std::span<const std::uint8_t> bytes) {
    if (stream == wire::Stream::Position) {
        ++s_.position_packets;
        ++s_.position_sizes[bytes.size()];
        if (have_pos_)
            s_.position_interval_us.add(static_cast<double>(time_ns - last_pos_ns_) / 1000.0);
        if (!have_pos_) first_pos_ns_ = time_ns;
        have_pos_ = true;
        last_pos_ns_ = time_ns;
        DecodedPosition pos;
        const PositionStatus st = decode_position(bytes, pos);
        s_.position.add(st);
        if (st == PositionStatus::Ok) {
            if (pos.rmc) ++s_.position_rmc;
            if (have_data_) {
                const std::uint32_t d =
                    (pos.timestamp_us + kMicrosPerHour - last_ts_) % kMicrosPerHour;
                s_.position_vs_data_us.add(d < kMicrosPerHour / 2 ? double(d)
                                                                  : double(d) - kMicrosPerHour);
            }
        }
        return;
    }
    if (stream != wire::Stream::Data) {
        ++s_.other_packets;
        return;
    }
    ++s_.data_packets;
    ++s_.data_sizes[bytes.size()];
    if (have_data_) s_.data_interval_us.add(static_cast<double>(time_ns - last_data_ns_) / 1000.0);
    if (!have_data_) first_data_ns_ = time_ns;
    last_data_ns_ = time_ns;
    if (bytes.size() >= kDataPacketSize) {
        // Raw fields, whatever the decoder says.
        s_.factory1[bytes[kFactoryOffset]]++;
        s_.factory2[bytes[kFactoryOffset + 1]]++;
        for (std::size_t b = 0; b < kBlocksPerPacket; ++b)
            s_.block_flags[static_cast<std::uint16_t>(bytes[kBlockSize * b] |
                                                      (bytes[kBlockSize * b + 1] << 8))]++;
    }
    const DecodeStatus st = decode_data(bytes, nullptr, scratch_);
    s_.decode.add(st);
    if (st != DecodeStatus::Ok) return;
    const DecodedPacket& p = scratch_;
    const ModelDescriptor& md = *p.model;
    if (!s_.model) {
        s_.model = md.model;
        s_.mode = p.mode;
    }
    if (have_data_) {
        const std::uint32_t d = (p.timestamp_us + kMicrosPerHour - last_ts_) % kMicrosPerHour;
        s_.timestamp_step_us.add(d < kMicrosPerHour / 2 ? double(d) : double(d) - kMicrosPerHour);
    }
    have_data_ = true;
    last_ts_ = p.timestamp_us;
    int prev_b = -1;
    for (int b = 0; b < kBlocksPerPacket; ++b) {
        const auto az = p.block_azimuth[static_cast<std::size_t>(b)];
        if (prev_b >= 0 && md.block_sequence(p.mode, b) != md.block_sequence(p.mode, prev_b)) {
            const int step =
                (az + kAzimuthCounts - p.block_azimuth[static_cast<std::size_t>(prev_b)]) %
                kAzimuthCounts;
            s_.azimuth_step_counts.add(step);
            ++s_.azimuth_step_histogram[step];
            const int dq = md.block_sequence(p.mode, b) - md.block_sequence(p.mode, prev_b);
            s_.azimuth_step_per_sequence_deg.add(0.01 * step / dq);
        }
        if (prev_b < 0 || md.block_sequence(p.mode, b) != md.block_sequence(p.mode, prev_b))
            prev_b = b;
    }
    for (const Firing& f : p.firing) {
        ++s_.slots;
        if (f.raw_distance == 0) ++s_.zero_distance_slots;
    }
}

CaptureStats CaptureStatsBuilder::result() const {
    CaptureStats r = s_;
    if (s_.data_packets > 1 && last_data_ns_ > first_data_ns_)
        r.data_rate_hz = static_cast<double>(s_.data_packets - 1) * 1e9 /
                         static_cast<double>(last_data_ns_ - first_data_ns_);
    if (s_.position_packets > 1 && last_pos_ns_ > first_pos_ns_)
        r.position_rate_hz = static_cast<double>(s_.position_packets - 1) * 1e9 /
                             static_cast<double>(last_pos_ns_ - first_pos_ns_);
    std::uint64_t best = 0;
    for (const auto& [step, n] : s_.azimuth_step_histogram)
        if (n > best) {
            best = n;
            r.azimuth_step_mode = step;
        }
    return r;
}

double CaptureStats::estimated_rpm() const {
    if (!model || azimuth_step_per_sequence_deg.n == 0) return 0;
    const double period_s = static_cast<double>(descriptor(*model).sequence_period_ns) * 1e-9;
    return azimuth_step_per_sequence_deg.mean / 360.0 / period_s * 60.0;
}

std::string CaptureStats::describe() const {
    std::string out;
    char buf[256];
    const auto line = [&](const char* fmt, auto... args) {
        std::snprintf(buf, sizeof buf, fmt, args...);
        out += buf;
        out += '\n';
    };
    line("data packets %llu (%.1f/s), position %llu (%.1f/s), other %llu",
         static_cast<unsigned long long>(data_packets), data_rate_hz,
         static_cast<unsigned long long>(position_packets), position_rate_hz,
         static_cast<unsigned long long>(other_packets));
    for (const auto& [size, n] : data_sizes)
        line("  data size %zu: %llu", size, static_cast<unsigned long long>(n));
    for (const auto& [b, n] : factory1)
        line("  byte 1204 0x%02X: %llu", b, static_cast<unsigned long long>(n));
    for (const auto& [b, n] : factory2)
        line("  byte 1205 0x%02X: %llu", b, static_cast<unsigned long long>(n));
    for (const auto& [f, n] : block_flags)
        line("  block flag 0x%04X: %llu", f, static_cast<unsigned long long>(n));
    line("azimuth step counts min %.0f max %.0f mean %.3f mode %d; per sequence %.5f deg; rpm %.1f",
         azimuth_step_counts.min, azimuth_step_counts.max, azimuth_step_counts.mean,
         azimuth_step_mode, azimuth_step_per_sequence_deg.mean, estimated_rpm());
    line("timestamp step us min %.0f max %.0f mean %.3f", timestamp_step_us.min,
         timestamp_step_us.max, timestamp_step_us.mean);
    line("decode errors %llu of %llu; zero-distance slots %llu of %llu",
         static_cast<unsigned long long>(decode.errors()),
         static_cast<unsigned long long>(decode.total()),
         static_cast<unsigned long long>(zero_distance_slots),
         static_cast<unsigned long long>(slots));
    if (position_packets > 0)
        line(
            "position ok %llu of %llu (rmc %llu); interval us %.0f..%.0f mean %.1f; "
            "pos-data clock %.0f..%.0f us",
            static_cast<unsigned long long>(position[PositionStatus::Ok]),
            static_cast<unsigned long long>(position.total()),
            static_cast<unsigned long long>(position_rmc), position_interval_us.min,
            position_interval_us.max, position_interval_us.mean, position_vs_data_us.min,
            position_vs_data_us.max);
    return out;
}

}  // namespace mirage::velodyne
