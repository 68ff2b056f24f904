// SPDX-License-Identifier: Apache-2.0
// PCL 1.13's HDLGrabber reads HDL-64E corrections only from a VeloView/PCL db.xml
// (boost_serialization.DB.points_.item.px.{id_, rotCorrection_, vertCorrection_ in degrees,
// distCorrection_, vertOffsetCorrection_, horizOffsetCorrection_ in cm}; docs/wire-formats.md
// §1.7), not from the ROS velodyne_pointcloud YAML that `mirage emulate --calibration-out` writes.
// This converts the latter into the former, so PCL decodes with exactly the file Mirage shipped.
#pragma once
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>

namespace mirage::test {

// Returns the number of lasers written; throws YAML::Exception on a malformed file.
inline int ros_calibration_to_pcl_db_xml(const std::string& yaml_path,
                                         const std::string& xml_path) {
    const YAML::Node root = YAML::LoadFile(yaml_path);
    const double deg = 180.0 / std::numbers::pi;
    std::ofstream out(xml_path);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\" ?>\n"
           "<!DOCTYPE boost_serialization>\n"
           "<boost_serialization signature=\"serialization::archive\" version=\"4\">\n"
           "<DB class_id=\"0\" tracking_level=\"0\" version=\"0\">\n"
           "<points_ class_id=\"1\" tracking_level=\"0\" version=\"0\">\n"
        << "<count>" << root["lasers"].size() << "</count>\n<item_version>1</item_version>\n";
    int n = 0;
    char buf[512];
    for (const auto& l : root["lasers"]) {
        std::snprintf(buf, sizeof buf,
                      "<item class_id=\"2\" tracking_level=\"0\" version=\"1\"><px class_id=\"3\" "
                      "tracking_level=\"0\" version=\"1\"><id_>%d</id_><rotCorrection_>%.12f"
                      "</rotCorrection_><vertCorrection_>%.12f</vertCorrection_><distCorrection_>"
                      "%.6f</distCorrection_><vertOffsetCorrection_>%.6f</vertOffsetCorrection_>"
                      "<horizOffsetCorrection_>%.6f</horizOffsetCorrection_></px></item>\n",
                      l["laser_id"].as<int>(), l["rot_correction"].as<double>() * deg,
                      l["vert_correction"].as<double>() * deg,
                      l["dist_correction"].as<double>() * 100.0,
                      l["vert_offset_correction"].as<double>() * 100.0,
                      l["horiz_offset_correction"].as<double>() * 100.0);
        out << buf;
        ++n;
    }
    out << "</points_>\n</DB>\n</boost_serialization>\n";
    return n;
}

}  // namespace mirage::test
