// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/decoder.hpp"

#include <cmath>
#include <numbers>

namespace mirage::ouster {

std::uint64_t DecodeCounters::errors() const {
    std::uint64_t n = imu_wrong_size;
    for (std::size_t i = 1; i < by_status.size(); ++i) n += by_status[i];
    return n;
}

Decoder::Decoder(Descriptor d) : d_(std::move(d)) {
    packet_.resize(d_);
    constexpr double kDeg = std::numbers::pi / 180.0;
    rows_.resize(d_.beams);
    for (std::size_t r = 0; r < d_.beams; ++r) {
        // θa = −beam_azimuth, φ = beam_altitude (§2.8).
        const double az = r < d_.azimuth_deg.size() ? -d_.azimuth_deg[r] * kDeg : 0.0;
        const double alt = r < d_.altitude_deg.size() ? d_.altitude_deg[r] * kDeg : 0.0;
        rows_[r] = {std::cos(az), std::sin(az), std::cos(alt), std::sin(alt)};
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            sensor_r_lidar_(i, j) = d_.lidar_to_sensor[static_cast<std::size_t>(4 * i + j)];
        sensor_t_lidar_mm_(i) = d_.lidar_to_sensor[static_cast<std::size_t>(4 * i + 3)];
    }
}

DecodeStatus Decoder::decode(std::span<const std::uint8_t> bytes) {
    ++counters_.packets;
    FooterCheck footer = FooterCheck::None;
    const DecodeStatus s = decode_lidar_packet(d_, bytes, packet_, &footer);
    ++counters_.by_status[static_cast<std::size_t>(s)];
    if (footer == FooterCheck::CrcValid) ++counters_.crc_valid;
    if (footer == FooterCheck::Placeholder) ++counters_.crc_placeholder;
    last_ok_ = s == DecodeStatus::Ok;
    if (!last_ok_) return s;

    const std::uint32_t W = d_.mode.columns;
    for (const auto& c : packet_.columns) {
        if (!c.valid()) {
            ++counters_.dropped_columns;
            continue;
        }
        if (!have_last_ || c.frame_id != last_frame_) {
            ++counters_.frames;
            // Columns lost at the end of the last frame and the start of this one (only when
            // the frame ID advanced by one; other jumps are counted as one gap).
            if (have_last_) {
                const auto step = static_cast<std::uint16_t>(c.frame_id - last_frame_);
                std::uint64_t missing = c.measurement_id;
                if (step == 1) missing += next_mid_ < W ? W - next_mid_ : 0;
                if (step != 1 || missing > 0) {
                    ++counters_.measurement_id_gaps;
                    counters_.missing_columns += missing;
                }
            }
            last_frame_ = c.frame_id;
        } else if (c.measurement_id != next_mid_) {
            ++counters_.measurement_id_gaps;
            if (c.measurement_id > next_mid_)
                counters_.missing_columns += c.measurement_id - next_mid_;
        }
        have_last_ = true;
        next_mid_ = std::uint32_t{c.measurement_id} + 1;
    }
    return s;
}

bool Decoder::decode_imu(std::span<const std::uint8_t> bytes, ImuPacket& out) {
    if (!decode_imu_packet(bytes, out)) {
        ++counters_.imu_wrong_size;
        return false;
    }
    ++counters_.imu_packets;
    return true;
}

Eigen::Vector3d Decoder::xyz(std::size_t row, std::uint16_t measurement_id, std::uint32_t range_mm,
                             PointFrame frame) const {
    if (row >= rows_.size()) return Eigen::Vector3d::Zero();
    const RowTrig& t = rows_[row];
    // θe = 2π(1 − m/W): cos θe = cos(2πm/W), sin θe = −sin(2πm/W).
    const double e = 2.0 * std::numbers::pi * double(measurement_id) / double(d_.mode.columns);
    const double ce = std::cos(e), se = -std::sin(e);
    const double c = ce * t.cos_az - se * t.sin_az;  // cos(θe + θa)
    const double s = se * t.cos_az + ce * t.sin_az;  // sin(θe + θa)
    const double n = d_.beam_origin_mm;
    const double r = double(range_mm) - n;
    Eigen::Vector3d p_mm(r * c * t.cos_alt + n * ce, r * s * t.cos_alt + n * se,
                         r * t.sin_alt + d_.beam_z_mm);
    if (frame == PointFrame::Sensor) p_mm = sensor_r_lidar_ * p_mm + sensor_t_lidar_mm_;
    return p_mm * 1e-3;
}

void Decoder::points(PointFrame frame, std::vector<OusterPoint>& out) const {
    if (!last_ok_) return;
    const std::size_t H = d_.beams;
    for (std::size_t ci = 0; ci < packet_.columns.size(); ++ci) {
        const ColumnHeader& c = packet_.columns[ci];
        if (!c.valid()) continue;
        for (std::size_t r = 0; r < H; ++r) {
            const Pixel& px = packet_.pixels[ci * H + r];
            if (px.range_mm == 0) continue;
            OusterPoint p;
            const Eigen::Vector3d v = xyz(r, c.measurement_id, px.range_mm, frame);
            p.x = v.x();
            p.y = v.y();
            p.z = v.z();
            p.timestamp_ns = c.timestamp_ns;
            p.range_mm = px.range_mm;
            p.row = static_cast<std::uint16_t>(r);
            p.measurement_id = c.measurement_id;
            p.frame_id = c.frame_id;
            p.reflectivity = px.reflectivity;
            p.signal = px.signal;
            p.nir = px.nir;
            out.push_back(p);
        }
    }
}

}  // namespace mirage::ouster
