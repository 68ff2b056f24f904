// SPDX-License-Identifier: Apache-2.0
// Metadata JSON (§2.7): our output reads back into the same descriptor, and the FW 2.x flat
// shape has the key structure of the real OS-2 capture's JSON.
#include "mirage/ouster/metadata.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "mirage/core/error.hpp"
#include "test_paths.hpp"

namespace mirage::ouster {
namespace {

using Json = nlohmann::json;

std::set<std::string> keys(const Json& v) {
    std::set<std::string> k;
    for (const auto& m : v.items()) k.insert(m.key());
    return k;
}

void expect_same(const Descriptor& a, const Descriptor& b) {
    EXPECT_EQ(a.line, b.line);
    EXPECT_EQ(a.beams, b.beams);
    EXPECT_EQ(a.mode, b.mode);
    EXPECT_EQ(a.profile, b.profile);
    EXPECT_EQ(a.columns_per_packet, b.columns_per_packet);
    EXPECT_EQ(a.altitude_deg, b.altitude_deg);  // shortest round-trip decimals: bit-exact
    EXPECT_EQ(a.azimuth_deg, b.azimuth_deg);
    EXPECT_EQ(a.beam_origin_mm, b.beam_origin_mm);
    EXPECT_EQ(a.lidar_to_sensor, b.lidar_to_sensor);
    EXPECT_EQ(a.imu_to_sensor, b.imu_to_sensor);
    EXPECT_EQ(a.serial, b.serial);
    EXPECT_EQ(a.init_id, b.init_id);
    EXPECT_EQ(a.udp_port_lidar, b.udp_port_lidar);
    EXPECT_EQ(a.udp_port_imu, b.udp_port_imu);
}

TEST(OusterMetadata, both_shapes_read_back_into_the_same_descriptor) {
    for (const char* name : {"os1-64-1024x10", "os2-128-2048x10", "os0-32-512x20"})
        for (Profile p : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8})
            for (MetadataShape shape : {MetadataShape::Nested, MetadataShape::Fw2Flat}) {
                const Descriptor d = make_descriptor(name, p);
                const std::string text = metadata_json(d, {shape});
                expect_same(descriptor_from_metadata(text, name), d);
            }
}

TEST(OusterMetadata, nested_shape_has_the_sections_the_sdk_reads) {
    const Descriptor d = make_descriptor("os1-128-1024x20", Profile::Rng19Rfl8Sig16Nir16);
    const Json v =
        Json::parse(metadata_json(d, {MetadataShape::Nested, TimestampMode::Ptp1588, "10.0.0.2"}));
    EXPECT_EQ(keys(v), (std::set<std::string>{"sensor_info", "beam_intrinsics", "lidar_data_format",
                                              "config_params", "imu_intrinsics", "lidar_intrinsics",
                                              "calibration_status"}));
    const Json& fmt = v.at("lidar_data_format");
    EXPECT_EQ(fmt.at("columns_per_frame"), 1024);
    EXPECT_EQ(fmt.at("pixels_per_column"), 128);
    EXPECT_EQ(fmt.at("column_window"), Json::array({0, 1023}));
    EXPECT_EQ(fmt.at("pixel_shift_by_row").size(), 128u);
    EXPECT_EQ(fmt.at("udp_profile_lidar"), "RNG19_RFL8_SIG16_NIR16");
    EXPECT_EQ(fmt.at("fps"), 20);
    const Json& cfg = v.at("config_params");
    EXPECT_EQ(cfg.at("lidar_mode"), "1024x20");
    EXPECT_EQ(cfg.at("timestamp_mode"), "TIME_FROM_PTP_1588");
    EXPECT_EQ(cfg.at("udp_dest"), "10.0.0.2");
    EXPECT_EQ(cfg.at("udp_port_imu"), 7503);
    const Json& info = v.at("sensor_info");
    EXPECT_EQ(info.at("prod_line"), "OS-1-128");
    EXPECT_EQ(info.at("prod_sn"), std::to_string(d.serial));
    EXPECT_EQ(info.at("initialization_id"), d.init_id);
    const Json& bi = v.at("beam_intrinsics");
    EXPECT_EQ(bi.at("beam_to_lidar_transform")[3].get<double>(), 15.806);
    // Integral entries are written as integers, as the sensor does ("1", not "1.0").
    EXPECT_TRUE(bi.at("beam_to_lidar_transform")[0].is_number_integer());
    EXPECT_EQ(v.at("calibration_status").at("reflectivity").at("valid"), false);
}

TEST(OusterMetadata, flat_shape_has_the_key_structure_of_the_real_os2_json) {
    MIRAGE_CAPTURE_OR_SKIP(json_path, "os2_128_rng19.json");
    std::ifstream in(json_path);
    std::stringstream ss;
    ss << in.rdbuf();
    const Json real = Json::parse(ss.str());
    const Descriptor d = load_metadata(json_path.string());
    const Json ours = Json::parse(metadata_json(d, {MetadataShape::Fw2Flat}));
    EXPECT_EQ(keys(ours), keys(real));
    EXPECT_EQ(keys(ours.at("data_format")), keys(real.at("data_format")));
    // Same values (and JSON number kinds) where the capture's descriptor defines them.
    for (const char* k : {"pixel_shift_by_row", "column_window"})
        EXPECT_EQ(ours.at("data_format").at(k), real.at("data_format").at(k)) << k;
    for (const char* k : {"initialization_id", "lidar_origin_to_beam_origin_mm", "udp_port_lidar",
                          "beam_altitude_angles", "beam_azimuth_angles", "imu_to_sensor_transform",
                          "lidar_to_sensor_transform"})
        EXPECT_EQ(ours.at(k), real.at(k)) << k;
    for (const char* k : {"prod_sn", "prod_line", "lidar_mode", "build_rev", "prod_pn"})
        EXPECT_EQ(ours.at(k), real.at(k)) << k;
}

TEST(OusterMetadata, malformed_metadata_names_the_input_and_key) {
    const auto error_of = [](const std::string& text) {
        try {
            descriptor_from_metadata(text, "m.json");
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error_of("{\"beam_altitude_angles\": [1, 2]"),
              "ouster metadata 'm.json': (document): line 1, column 32: syntax error while parsing "
              "object - unexpected end of input; expected '}'");
    EXPECT_EQ(error_of("[1, 2]"), "ouster metadata 'm.json': (document): expected an object");
    const std::string angles64 = [] {
        std::string s = "[";
        for (int i = 0; i < 64; ++i) s += (i ? ", " : "") + std::to_string(i);
        return s + "]";
    }();
    EXPECT_EQ(error_of("{\"beam_altitude_angles\": " + angles64 +
                       ", \"beam_azimuth_angles\": " + angles64 + ", \"lidar_mode\": \"999x1\"}")
                  .rfind("ouster metadata 'm.json': lidar_mode: ouster: unknown lidar mode", 0),
              0u);
    EXPECT_EQ(error_of("{\"beam_altitude_angles\": " + angles64 + ", \"beam_azimuth_angles\": [1]" +
                       ", \"lidar_mode\": \"1024x10\"}"),
              "ouster metadata 'm.json': beam_azimuth_angles: expected 64 angles");
    EXPECT_THROW(load_metadata("/nonexistent/x.json"), IoError);
}

// Integers the descriptor stores unsigned: a negative, fractional or too large value is refused
// naming the key, never converted (fuzz_ouster_metadata: UBSan float-cast-overflow).
TEST(OusterMetadata, unsigned_fields_out_of_range_are_refused) {
    const auto with = [](const std::string& key, double value) {
        Json j = Json::parse(metadata_json(make_descriptor("os1-64-1024x10", Profile::Legacy),
                                           {MetadataShape::Fw2Flat}));
        j[key] = value;
        try {
            descriptor_from_metadata(j.dump(), "m.json");
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(with("initialization_id", -898272),
              "ouster metadata 'm.json': initialization_id: expected a whole number from 0 to "
              "4294967295");
    EXPECT_EQ(with("initialization_id", 1.5).find("initialization_id: expected a whole"), 26u);
    EXPECT_EQ(with("udp_port_lidar", 70000),
              "ouster metadata 'm.json': udp_port_lidar: expected a whole number from 0 to 65535");
    EXPECT_EQ(with("udp_port_imu", -1).find("udp_port_imu: expected a whole"), 26u);
    EXPECT_EQ(with("udp_port_imu", 7503), "no error");
}

}  // namespace
}  // namespace mirage::ouster
