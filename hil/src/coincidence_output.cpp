// SPDX-License-Identifier: Apache-2.0
#include "coincidence_output.hpp"

#include <algorithm>

namespace mirage::hil {

std::vector<core::PointRecord> coincidence_records(std::span<const render::CoincidencePoint> pts,
                                                   const Job& job) {
    std::vector<core::PointRecord> recs(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
        auto& r = recs[k];
        r.x = pts[k].x, r.y = pts[k].y, r.z = pts[k].z;
        r.t = job.options.start;
        r.n_laser = pts[k].expected;
        r.intensity = static_cast<std::uint16_t>(std::min(65535.0, 1000.0 * pts[k].expected));
        r.classification = pts[k].classification;
        r.point_source_id = job.sensor.point_source_id;
    }
    return recs;
}

void write_coincidence_las(const std::string& path, const Job& job, const las::LasWriterOptions& lo,
                           std::span<const core::PointRecord> records) {
    las::LasWriterOptions plain = lo;
    plain.event_fields = false;
    las::LasWriter w(path, job.scene->georef, plain);
    w.write(records);
    w.close();
}

}  // namespace mirage::hil
