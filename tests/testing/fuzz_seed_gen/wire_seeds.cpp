// SPDX-License-Identifier: Apache-2.0
// Seeds of the wire-format targets: packets from the Velodyne packetizer and the Ouster encoders.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_decode_one.hpp"
#include "fuzz_ouster_kinds.hpp"
#include "mirage/ouster/imu.hpp"
#include "mirage/ouster/lidar_packet.hpp"
#include "mirage/ouster/metadata.hpp"
#include "seed_writer.hpp"

namespace mirage::testing::seeds {
namespace {

// Every model × return mode, then the three position layouts (fuzz_decode_one.hpp).
void velodyne(SeedWriter& w) {
    const auto& packets = velodyne::test::seed_packets();
    for (std::size_t i = 0; i < packets.size(); ++i)
        w.put("fuzz_velodyne_decode", "packet_" + std::to_string(i), packets[i]);
}

// A lidar packet of `d`: columns first_mid.., ranges on every other pixel, valid columns.
std::vector<std::uint8_t> ouster_packet(const ouster::Descriptor& d, std::uint16_t first_mid) {
    ouster::LidarPacket p;
    p.resize(d);
    p.header.frame_id = 7;
    p.header.init_id = d.init_id;
    p.header.serial = d.serial;
    for (std::uint16_t c = 0; c < d.columns_per_packet; ++c) {
        auto& col = p.columns[c];
        col.measurement_id = static_cast<std::uint16_t>(first_mid + c);
        col.frame_id = 7;
        col.encoder_count = d.encoder_count(col.measurement_id);
        col.timestamp_ns = 1'000'000'000ull + 97'656ull * col.measurement_id;
        col.status = ouster::valid_column_status(d);
        for (std::uint16_t r = 0; r < d.beams; r += 2) {
            auto& px = p.pixel(c, r, d.beams);
            px.range_mm = 1000u + 37u * r + c;
            px.reflectivity = static_cast<std::uint16_t>(r);
            px.signal = 100;
            px.nir = 48;
        }
    }
    std::vector<std::uint8_t> out(d.packet_bytes());
    if (!ouster::encode_lidar_packet(d, p, out)) throw std::runtime_error("ouster seed encode");
    return out;
}

// Kinds whose packet is small enough for a committed seed (≤ 4.5 KB): every profile is among them.
void ouster_lidar(SeedWriter& w) {
    const auto& kinds = ouster::test::fuzz_kinds();
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        const auto& d = kinds[k];
        if (d.packet_bytes() > 4500) continue;
        const auto mode = static_cast<std::uint8_t>(k | 0x80);  // harness writes the CRC
        w.put("fuzz_ouster_decode", "lidar_" + std::to_string(k), mode, ouster_packet(d, 32));
        if (d.packet_bytes() <= 1500) {  // two in a row, the second not following on: a gap
            auto two = ouster_packet(d, 0);
            const auto next =
                ouster_packet(d, static_cast<std::uint16_t>(2 * d.columns_per_packet));
            two.insert(two.end(), next.begin(), next.end());
            w.put("fuzz_ouster_decode", "gap_" + std::to_string(k), mode, two);
        }
    }
}

void ouster_imu(SeedWriter& w) {
    ouster::ImuPacket imu;
    imu.sys_ns = 1'000'000'000;
    imu.accel_ns = imu.sys_ns + 214'550;
    imu.gyro_ns = imu.sys_ns + 437'320;
    imu.accel_g = {0.01f, -0.02f, 1.0f};
    imu.gyro_dps = {0.1f, 0.0f, -0.3f};
    std::vector<std::uint8_t> b(ouster::kImuPacketBytes);
    ouster::encode_imu_packet(imu, b);
    w.put("fuzz_ouster_decode", "imu", 0, b);
}

void ouster_metadata(SeedWriter& w) {
    const auto d = ouster::make_descriptor(ouster::ProductLine::OS1, 32, {512, 10},
                                           ouster::Profile::Rng19Rfl8Sig16Nir16);
    w.put("fuzz_ouster_metadata", "nested_rng19.json", ouster::metadata_json(d));
    ouster::MetadataOptions flat;
    flat.shape = ouster::MetadataShape::Fw2Flat;
    const auto l =
        ouster::make_descriptor(ouster::ProductLine::OS0, 32, {1024, 20}, ouster::Profile::Legacy);
    w.put("fuzz_ouster_metadata", "fw2_flat_legacy.json", ouster::metadata_json(l, flat));
}

}  // namespace

void write_wire_seeds(SeedWriter& w) {
    velodyne(w);
    ouster_lidar(w);
    ouster_imu(w);
    ouster_metadata(w);
}

}  // namespace mirage::testing::seeds
