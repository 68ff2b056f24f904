// SPDX-License-Identifier: Apache-2.0
// ROS velodyne_pointcloud calibration YAML.
#include "mirage/velodyne/calibration.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <numbers>

namespace mirage::velodyne {
namespace {

constexpr double kRad = std::numbers::pi / 180.0;

TEST(VelodyneCalibration, hdl64e_yaml_holds_the_rendered_angles_in_ros_format) {
    const ModelDescriptor& md = descriptor(Model::Hdl64eS3);
    const YAML::Node y = YAML::Load(calibration_yaml(md));
    EXPECT_EQ(y["num_lasers"].as<int>(), 64);
    EXPECT_DOUBLE_EQ(y["distance_resolution"].as<double>(), 0.002);
    ASSERT_EQ(y["lasers"].size(), 64u);
    for (int l = 0; l < 64; ++l) {
        const YAML::Node n = y["lasers"][static_cast<std::size_t>(l)];
        EXPECT_EQ(n["laser_id"].as<int>(), l);
        const auto& li = md.laser[static_cast<std::size_t>(l)];
        // Decoders compute azimuth − rot_correction, so rot_correction = −δ.
        EXPECT_NEAR(n["rot_correction"].as<double>(), -li.azimuth_offset_deg * kRad, 1e-15);
        EXPECT_NEAR(n["vert_correction"].as<double>(), li.elevation_deg * kRad, 1e-15);
        for (const char* zero :
             {"dist_correction", "dist_correction_x", "dist_correction_y", "vert_offset_correction",
              "horiz_offset_correction", "focal_distance", "focal_slope"})
            EXPECT_EQ(n[zero].as<double>(), 0.0) << zero;
        EXPECT_EQ(n["max_intensity"].as<int>(), 255);
    }
    // The xiesc unit's first laser, as in ros-drivers/velodyne params/64e_s3-xiesc.yaml.
    EXPECT_NEAR(y["lasers"][0]["rot_correction"].as<double>(), -0.07648247457737148, 1e-15);
    EXPECT_NEAR(y["lasers"][0]["vert_correction"].as<double>(), -0.1261818455292898, 1e-15);
}

TEST(VelodyneCalibration, other_models_get_the_same_format) {
    for (Model m : {Model::Vlp16, Model::Vlp16HiRes, Model::Vlp32c, Model::Hdl32e}) {
        const ModelDescriptor& md = descriptor(m);
        const YAML::Node y = YAML::Load(calibration_yaml(md));
        EXPECT_EQ(y["num_lasers"].as<int>(), md.lasers);
        EXPECT_DOUBLE_EQ(y["distance_resolution"].as<double>(), md.distance_lsb_m);
        ASSERT_EQ(static_cast<int>(y["lasers"].size()), md.lasers);
    }
    const YAML::Node v32 = YAML::Load(calibration_yaml(descriptor(Model::Vlp32c)));
    // VLP-32C laser 1: ρ = 4.2° (docs/wire-formats.md §1.7, ROS column), elevation −1°.
    EXPECT_NEAR(v32["lasers"][1]["rot_correction"].as<double>(), 4.2 * kRad, 1e-15);
    EXPECT_NEAR(v32["lasers"][1]["vert_correction"].as<double>(), -1.0 * kRad, 1e-15);
    const YAML::Node v16 = YAML::Load(calibration_yaml(descriptor(Model::Vlp16)));
    EXPECT_NEAR(v16["lasers"][15]["vert_correction"].as<double>(), 15.0 * kRad, 1e-15);
    EXPECT_EQ(v16["lasers"][15]["rot_correction"].as<double>(), 0.0);
}

}  // namespace
}  // namespace mirage::velodyne
