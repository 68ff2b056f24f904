// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/calibration.hpp"

#include <cstdio>
#include <numbers>

namespace mirage::velodyne {

std::string calibration_yaml(const ModelDescriptor& model) {
    constexpr double kRad = std::numbers::pi / 180.0;
    std::string out = "# " + std::string(model.product) +
                      " calibration written by Mirage (ROS velodyne_pointcloud format)\nlasers:\n";
    char buf[512];
    for (int l = 0; l < model.lasers; ++l) {
        const LaserInfo& li = model.laser[static_cast<std::size_t>(l)];
        std::snprintf(buf, sizeof buf,
                      "- {dist_correction: 0.0, dist_correction_x: 0.0, dist_correction_y: 0.0, "
                      "focal_distance: 0.0, focal_slope: 0.0, horiz_offset_correction: 0.0, "
                      "laser_id: %d, max_intensity: 255, min_intensity: 0, rot_correction: %.17g, "
                      "vert_correction: %.17g, vert_offset_correction: 0.0}\n",
                      l, -li.azimuth_offset_deg * kRad + 0.0, li.elevation_deg * kRad);
        out += buf;
    }
    std::snprintf(buf, sizeof buf, "num_lasers: %d\ndistance_resolution: %.3f\n", model.lasers,
                  model.distance_lsb_m);
    out += buf;
    return out;
}

}  // namespace mirage::velodyne
