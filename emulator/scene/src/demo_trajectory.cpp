// SPDX-License-Identifier: Apache-2.0
// Demo drive and demo flight through the generated town.
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "demo_layout.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/demo_town.hpp"

namespace mirage::scene {

namespace {

constexpr double kCarSpeed = 10.0;     // m/s
constexpr double kSensorHeight = 1.8;  // platform origin above the road surface, m
constexpr std::int64_t kCarStepNs = 10'000'000;
constexpr double kFlightSpeed = 50.0;    // m/s
constexpr double kFlightHeight = 300.0;  // above the terrain at the town centre, m
constexpr std::int64_t kFlightStepNs = 100'000'000;
constexpr double kPassSpeed = 10.0;     // m/s: a dwell of ~1 000 gates per 0.5 m cell (§8)
constexpr double kPassHeight = 1200.0;  // above the vehicle's ground, m

// Sample offsets 0, step, 2·step, ... and the duration itself as the last one.
std::vector<std::int64_t> sample_offsets(core::Nanos duration, std::int64_t step, const char* who) {
    if (duration.count() < 0) {
        throw ConfigError(std::string(who) + ": duration must not be negative");
    }
    if (duration.count() / step > 100'000'000) {
        throw ConfigError(std::string(who) + ": duration too long");
    }
    std::vector<std::int64_t> t;
    for (std::int64_t k = 0; k * step < duration.count(); ++k) t.push_back(k * step);
    t.push_back(duration.count());
    return t;
}

}  // namespace

core::Trajectory demo_car_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                     core::Nanos duration) {
    const demo::Hills hills(opt.seed);
    const demo::RoadLoop lane = demo::road_loop(opt).offset(demo::kLaneOffset);
    std::vector<core::StampedPose> samples;
    for (std::int64_t ns : sample_offsets(duration, kCarStepNs, "demo car trajectory")) {
        const double s = kCarSpeed * static_cast<double>(ns) * 1e-9;
        Eigen::Vector2d p, t;
        lane.at(s, p, t);
        const Eigen::Vector3d n = hills.normal(p.x(), p.y());
        Eigen::Vector3d x(t.x(), t.y(), 0.0);
        x = (x - x.dot(n) * n).normalized();
        Eigen::Matrix3d r;
        r.col(0) = x;
        r.col(1) = n.cross(x);
        r.col(2) = n;
        core::Pose pose;
        const Eigen::Vector3d road(p.x(), p.y(), hills.height(p.x(), p.y()) + demo::kRoadLift);
        // Straight above the lane point, so the horizontal track is exactly the lane at 10 m/s.
        pose.position = road + Eigen::Vector3d(0, 0, kSensorHeight);
        pose.attitude = Eigen::Quaterniond(r).normalized();
        samples.push_back({start + core::Nanos(ns), pose});
    }
    return core::Trajectory(std::move(samples), core::Interpolation::Cubic);
}

core::Trajectory demo_flight_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                        core::Nanos duration) {
    const double z = demo::Hills(opt.seed).height(0.0, 0.0) + kFlightHeight;
    const double half = 0.5 * kFlightSpeed * static_cast<double>(duration.count()) * 1e-9;
    std::vector<core::StampedPose> samples;
    for (std::int64_t ns : sample_offsets(duration, kFlightStepNs, "demo flight trajectory")) {
        core::Pose pose;
        pose.position = {-half + kFlightSpeed * static_cast<double>(ns) * 1e-9, 0.0, z};
        pose.attitude = Eigen::Quaterniond::Identity();  // yaw 0: heading east, level
        samples.push_back({start + core::Nanos(ns), pose});
    }
    return core::Trajectory(std::move(samples), core::Interpolation::Cubic);
}

core::Pose camouflaged_vehicle_pose(const DemoTownOptions& opt) {
    if (!opt.camouflaged_vehicle)
        throw ConfigError("demo town: these options place no camouflaged vehicle");
    const demo::RoadLoop loop = demo::road_loop(opt);
    const demo::CamouflageSite site =
        demo::camouflage_site(opt, loop, demo::building_lots(opt, loop));
    const Eigen::Vector2d c = site.centre;
    core::Pose pose;
    pose.position = {c.x(), c.y(), demo::Hills(opt.seed).height(c.x(), c.y())};
    pose.attitude = Eigen::AngleAxisd(site.yaw, Eigen::Vector3d::UnitZ());
    return pose;
}

core::Trajectory demo_camouflage_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                            core::Nanos duration) {
    const Eigen::Vector3d v = camouflaged_vehicle_pose(opt).position;
    const double half = 0.5 * kPassSpeed * static_cast<double>(duration.count()) * 1e-9;
    std::vector<core::StampedPose> samples;
    for (std::int64_t ns : sample_offsets(duration, kFlightStepNs, "demo camouflage trajectory")) {
        core::Pose pose;
        pose.position = {v.x() - half + kPassSpeed * static_cast<double>(ns) * 1e-9, v.y(),
                         v.z() + kPassHeight};
        pose.attitude = Eigen::Quaterniond::Identity();
        samples.push_back({start + core::Nanos(ns), pose});
    }
    return core::Trajectory(std::move(samples), core::Interpolation::Cubic);
}

}  // namespace mirage::scene
