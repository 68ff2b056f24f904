// SPDX-License-Identifier: Apache-2.0
#include "ouster_capture_stats.hpp"

#include <algorithm>
#include <map>
#include <vector>

namespace mirage::ouster {
namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

template <class T>
T mode_of(const std::map<T, std::uint64_t>& counts) {
    T best{};
    std::uint64_t n = 0;
    for (const auto& [value, count] : counts)
        if (count > n) {
            best = value;
            n = count;
        }
    return best;
}

std::vector<double> intervals(std::span<const TimedPacket> packets) {
    std::vector<double> v;
    for (std::size_t i = 1; i < packets.size(); ++i)
        v.push_back(double(packets[i].time_ns - packets[i - 1].time_ns));
    return v;
}

}  // namespace

CaptureStats capture_stats(const Descriptor& d, std::span<const TimedPacket> lidar,
                           std::span<const TimedPacket> imu) {
    CaptureStats s;
    Decoder dec(d);
    std::map<std::size_t, std::uint64_t> sizes, imu_sizes;
    std::map<std::int64_t, std::uint64_t> mid_steps, enc_steps;
    std::map<std::uint16_t, std::uint32_t> per_frame;
    std::vector<double> ts_steps;
    bool have_prev = false;
    ColumnHeader prev;
    for (const auto& p : lidar) {
        ++sizes[p.bytes.size()];
        if (dec.decode(p.bytes) != DecodeStatus::Ok) {
            have_prev = false;
            continue;
        }
        ++per_frame[dec.packet().header.frame_id];
        for (const auto& c : dec.packet().columns) {
            if (!c.valid()) continue;
            if (have_prev && c.frame_id == prev.frame_id) {
                mid_steps[std::int64_t{c.measurement_id} - prev.measurement_id]++;
                if (d.profile == Profile::Legacy)
                    enc_steps[std::int64_t{c.encoder_count} - prev.encoder_count]++;
                if (c.measurement_id == prev.measurement_id + 1)
                    ts_steps.push_back(double(c.timestamp_ns) - double(prev.timestamp_ns));
            }
            prev = c;
            have_prev = true;
        }
    }
    std::vector<double> imu_ts;
    for (const auto& p : imu) {
        ++imu_sizes[p.bytes.size()];
        ImuPacket ip;
        if (dec.decode_imu(p.bytes, ip)) imu_ts.push_back(double(ip.sys_ns));
    }
    const DecodeCounters& k = dec.counters();
    s.lidar_packets = lidar.size();
    s.lidar_packet_bytes = mode_of(sizes);
    s.decode_errors = k.errors();
    s.crc_valid = k.crc_valid;
    s.crc_placeholder = k.crc_placeholder;
    s.measurement_id_gaps = k.measurement_id_gaps;
    s.columns_per_packet = d.columns_per_packet;
    s.column_ts_step_ns = median(ts_steps);
    s.measurement_id_step = mode_of(mid_steps);
    s.encoder_step = mode_of(enc_steps);
    for (const auto& [frame, n] : per_frame) s.packets_per_frame = std::max(s.packets_per_frame, n);
    s.lidar_packet_interval_ns = median(intervals(lidar));
    s.imu_packets = imu.size();
    s.imu_packet_bytes = mode_of(imu_sizes);
    s.imu_interval_ns = median(intervals(imu));
    std::vector<double> steps;
    for (std::size_t i = 1; i < imu_ts.size(); ++i) steps.push_back(imu_ts[i] - imu_ts[i - 1]);
    s.imu_ts_step_ns = median(steps);
    return s;
}

}  // namespace mirage::ouster
