// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "mirage/velodyne/model.hpp"

namespace mirage::velodyne {

// Calibration file in the YAML format ROS velodyne_pointcloud reads (its params/*.yaml):
// `lasers:` with laser_id, rot_correction and vert_correction (radians; decoders use
// azimuth − rot_correction, so rot_correction = −δ), zero distance/offset corrections (Mirage
// renders without them), min/max intensity, focal distance/slope; then num_lasers and
// distance_resolution (m). Pure: the CLI writes it next to an emulated HDL-64E S3 stream (which
// has no fixed table, §1.7), and it serves every other model too.
std::string calibration_yaml(const ModelDescriptor& model);

}  // namespace mirage::velodyne
