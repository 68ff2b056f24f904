// SPDX-License-Identifier: Apache-2.0
// Coincidence-processed points as LAS (docs/photon-counting.md §5), shared by `render` and `demo`.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "job.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/render/coincidence.hpp"

namespace mirage::hil {

// As LAS records: GPS time of the run's start, the expected events per gate in n_laser and
// ×1000 as intensity, the class of most of the bin's events.
std::vector<core::PointRecord> coincidence_records(std::span<const render::CoincidencePoint> pts,
                                                   const Job& job);

// Written with the run's LAS options less the photon-event fields.
void write_coincidence_las(const std::string& path, const Job& job, const las::LasWriterOptions& lo,
                           std::span<const core::PointRecord> records);

}  // namespace mirage::hil
