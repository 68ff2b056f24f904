// SPDX-License-Identifier: Apache-2.0
// Per-model packet timing: azimuth and timestamp steps, packet rates, hour wrap.
#include <gtest/gtest.h>

#include <cmath>

#include "mirage/core/error.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/velodyne/sensor_clock.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

std::vector<test::CollectedPacket> empty_stream(const ModelDescriptor& md, ReturnMode mode,
                                                double rpm, core::GpsTime start,
                                                std::uint64_t packets) {
    std::vector<test::CollectedPacket> out;
    PacketizerOptions o;
    o.mode = mode;
    o.rpm = rpm;
    o.start = start;
    o.position_packets = false;
    Packetizer pk(md, o, test::collect_into(out));
    pk.advance_to(packets * pk.pulses_per_packet());
    return out;
}

TEST(VelodyneTiming, packet_rates_match_the_spec_table) {
    // docs/wire-formats.md §1.4: packets/s single (dual).
    EXPECT_NEAR(descriptor(Model::Vlp16).packets_per_second(ReturnMode::Strongest), 753.5, 0.6);
    EXPECT_NEAR(descriptor(Model::Vlp16).packets_per_second(ReturnMode::Dual), 1507.0, 1.2);
    EXPECT_NEAR(descriptor(Model::Vlp32c).packets_per_second(ReturnMode::Strongest), 1507.0, 1.0);
    EXPECT_NEAR(descriptor(Model::Hdl32e).packets_per_second(ReturnMode::Strongest), 1808.4, 0.5);
    EXPECT_NEAR(descriptor(Model::Hdl32e).packets_per_second(ReturnMode::Dual), 3616.9, 0.5);
    // HDL-64E S3: 6 sequences of 48 µs per packet; dual 3 → 6944.4/s.
    EXPECT_EQ(descriptor(Model::Hdl64eS3).packet_period_ns(ReturnMode::Strongest), 288'000);
    EXPECT_EQ(descriptor(Model::Hdl64eS3).packet_period_ns(ReturnMode::Dual), 144'000);
    EXPECT_EQ(descriptor(Model::Vlp16).packet_period_ns(ReturnMode::Strongest), 1'327'104);
    EXPECT_EQ(descriptor(Model::Hdl32e).packet_period_ns(ReturnMode::Strongest), 552'960);
}

TEST(VelodyneTiming, azimuth_and_timestamp_steps_follow_the_closed_form_at_two_rpms) {
    const core::GpsTime start = core::parse_time("2023-06-30T08:15:00.000250Z");
    for (Model m : kAllModels)
        for (ReturnMode mode : {ReturnMode::Strongest, ReturnMode::Dual})
            for (double rpm : {600.0, 900.0}) {
                const ModelDescriptor& md = descriptor(m);
                SCOPED_TRACE(std::string(md.name) + " " + to_string(mode) + " " +
                             std::to_string(rpm));
                const std::uint64_t n = 200;
                const auto out = empty_stream(md, mode, rpm, start, n);
                ASSERT_EQ(out.size(), n);
                const double period_us = static_cast<double>(md.packet_period_ns(mode)) / 1e3;
                // Rotor advance per packet: 360°·f·packet period, in 0.01° counts.
                const double az_per_packet = 36000.0 * rpm / 60.0 * period_us * 1e-6;
                DecodedPacket first, prev, d;
                for (std::uint64_t p = 0; p < n; ++p) {
                    ASSERT_EQ(decode_data(out[p].bytes, &md, d), DecodeStatus::Ok);
                    if (p == 0) first = d;
                    if (p > 0) {
                        const double dts = d.timestamp_us - double(prev.timestamp_us);
                        EXPECT_GE(dts, std::floor(period_us));
                        EXPECT_LE(dts, std::ceil(period_us));
                        const int daz =
                            (d.block_azimuth[0] + 36000 - prev.block_azimuth[0]) % 36000;
                        EXPECT_LE(std::abs(daz - az_per_packet), 1.0);
                        // Send times are exactly one packet period apart.
                        EXPECT_EQ((out[p].time - out[p - 1].time).count(),
                                  md.packet_period_ns(mode));
                    }
                    prev = d;
                }
                // No drift: the total over n − 1 packets is the closed form to 1 µs / 1 count.
                const double total_ts = prev.timestamp_us - double(first.timestamp_us);
                EXPECT_LE(std::abs(total_ts - (n - 1) * period_us), 1.0);
                const double total_az = std::fmod((n - 1) * az_per_packet, 36000.0);
                const int got_az = (prev.block_azimuth[0] + 36000 - first.block_azimuth[0]) % 36000;
                EXPECT_LE(std::abs(got_az - total_az), 1.0);
            }
}

TEST(VelodyneTiming, timestamp_wraps_at_the_top_of_the_utc_hour) {
    const ModelDescriptor& md = descriptor(Model::Vlp16);
    // 2 ms before 11:00:00 UTC: the third packet is past the hour.
    const core::GpsTime start = core::parse_time("2024-01-01T10:59:59.998Z");
    const auto out = empty_stream(md, ReturnMode::Strongest, 600, start, 4);
    std::vector<std::uint32_t> ts;
    for (const auto& p : out) {
        DecodedPacket d;
        ASSERT_EQ(decode_data(p.bytes, &md, d), DecodeStatus::Ok);
        ts.push_back(d.timestamp_us);
    }
    EXPECT_EQ(ts[0], 3'599'998'000u);
    EXPECT_EQ(ts[1], 3'599'999'327u);  // + 1327.104 µs, floor
    EXPECT_EQ(ts[2], 654u);            // 3 599 998 000 + 2654.208 − 3 600 000 000
    EXPECT_EQ(ts[3], 1981u);
    EXPECT_EQ(micros_past_hour(core::parse_time("2024-01-01T11:00:00Z")), 0u);
    EXPECT_EQ(micros_past_hour(core::parse_time("2024-01-01T10:59:59.999999Z")), 3'599'999'999u);
}

TEST(VelodyneTiming, rpm_outside_the_model_range_is_a_config_error) {
    PacketizerOptions o;
    o.rpm = 1500;
    try {
        Packetizer pk(descriptor(Model::Vlp16), o, {});
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "velodyne vlp16: rpm 1500 outside 300–1200");
    }
    o.rpm = 299;
    EXPECT_THROW(Packetizer(descriptor(Model::Hdl32e), o, {}), ConfigError);
    o.rpm = 300;
    EXPECT_NO_THROW(Packetizer(descriptor(Model::Hdl32e), o, {}));
}

TEST(VelodyneTiming, sensor_of_another_model_is_rejected) {
    const sensor::SensorModel hdl = sensor::preset("hdl32e");
    EXPECT_THROW(Packetizer(descriptor(Model::Vlp32c), ReturnMode::Strongest, hdl, {}, {}),
                 ConfigError);
    EXPECT_THROW(Packetizer(descriptor(Model::Vlp16HiRes), ReturnMode::Strongest,
                            sensor::preset("vlp16"), {}, {}),
                 ConfigError);
    EXPECT_THROW(parse_return_mode("both"), ConfigError);
    EXPECT_EQ(parse_return_mode("dual"), ReturnMode::Dual);
}

TEST(VelodyneTiming, hdl64e_status_bytes_cycle_through_time_and_gps_records) {
    const ModelDescriptor& md = descriptor(Model::Hdl64eS3);
    const core::GpsTime start = core::parse_time("2019-11-23T17:42:09Z");
    const auto out = empty_stream(md, ReturnMode::Strongest, 600, start, 32);
    const std::string types = "HMSDNYGTV";
    const int values[] = {17, 42, 9, 23, 11, 19, 'A', 40, 0x29};
    for (std::size_t p = 0; p < out.size(); ++p) {
        const std::size_t pos = p % 16;
        if (pos < 9) {
            EXPECT_EQ(out[p].bytes[1204], types[pos]) << p;
            EXPECT_EQ(out[p].bytes[1205], values[pos]) << p;
        } else {
            EXPECT_EQ(out[p].bytes[1204], 0) << p;  // calibration bytes: not emulated
        }
    }
}

TEST(VelodyneTiming, product_byte_can_be_set_apart_from_the_geometry) {
    PacketizerOptions o;
    o.product_id = 0x21;
    o.position_packets = false;
    std::vector<test::CollectedPacket> out;
    Packetizer pk(descriptor(Model::Vlp16), o, test::collect_into(out));
    pk.advance_to(pk.pulses_per_packet());
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].bytes[1205], 0x21);
    DecodedPacket d;
    EXPECT_EQ(decode_data(out[0].bytes, &descriptor(Model::Vlp16), d),
              DecodeStatus::ProductMismatch);
}

}  // namespace
}  // namespace mirage::velodyne
