// SPDX-License-Identifier: Apache-2.0
#include "mirage/wire/setup.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/ouster/descriptor.hpp"
#include "mirage/ouster/imu.hpp"
#include "mirage/ouster/metadata.hpp"
#include "mirage/ouster/packetizer.hpp"
#include "mirage/ouster/sensor_clock.hpp"
#include "mirage/sensor/spinning.hpp"
#include "mirage/velodyne/calibration.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/velodyne/packetizer.hpp"

namespace mirage::wire {
namespace {

[[noreturn]] void no_wire_format(const std::string& name) {
    throw ConfigError(fmt::format(
        "emulate: sensor '{}' has no wire format; use a Velodyne preset (vlp16, vlp16-hires, "
        "vlp32c, hdl32e, hdl64e-s3) or an Ouster preset (os<0|1|2>-<32|64|128>-<W>x<F>)",
        name));
}

// Position of the sensor for the Velodyne $GPRMC: the trajectory through the scene's georef.
// A receiver reports one fix per UTC second, so the fix is computed once per second, with the
// PROJ transform set up once (setting it up costs ~10 ms; position packets come every few ms).
velodyne::PositionFn position_fn(const WireContext& ctx) {
    const scene::Scene* s = &ctx.scene;
    const core::Trajectory* traj = &ctx.trajectory;
    struct Cache {
        std::int64_t second = std::numeric_limits<std::int64_t>::min();
        velodyne::GeoFix fix;
        std::shared_ptr<core::GeodeticConverter> to_geodetic;  // null: no CRS
    };
    auto cache = std::make_shared<Cache>();
    if (s->georef.has_crs())
        cache->to_geodetic = std::make_shared<core::GeodeticConverter>(s->georef);
    return [traj, cache](core::GpsTime t) {
        const std::int64_t second = core::unix_ns_from_gps(t) / 1'000'000'000;
        if (second == cache->second) return cache->fix;
        velodyne::GeoFix fix;
        fix.valid = false;  // no CRS or no projection: the receiver reports "no fix"
        if (cache->to_geodetic) {
            t = core::gps_from_unix_ns(second * 1'000'000'000);  // the fix's own instant
            const Eigen::Vector3d p = traj->at(t).position;
            // Speed and course over ground from ±0.5 s (a 1 Hz receiver's view).
            const core::Nanos h = std::chrono::milliseconds(500);
            const Eigen::Vector3d v = traj->at(t + h).position - traj->at(t - h).position;
            try {
                const Eigen::Vector3d llh = cache->to_geodetic->geodetic_from_local(p);
                fix.lat_deg = llh.x();
                fix.lon_deg = llh.y();
                fix.speed_knots = v.head<2>().norm() * 3600.0 / 1852.0;  // m per 1 s → knots
                double course = std::atan2(v.x(), v.y()) * 180.0 / std::numbers::pi;
                if (course < 0) course += 360.0;
                fix.course_deg = course;
                fix.valid = true;
            } catch (const Error&) {
                // A point PROJ cannot invert (far outside the zone): no fix this second.
            }
        }
        cache->second = second;
        cache->fix = fix;
        return fix;
    };
}

}  // namespace

void prepare_sensor(sensor::SensorModel& sensor, const WireOptions& options, double rpm) {
    const sensor::WireFamily family = sensor.wire.family;
    if (family == sensor::WireFamily::None) no_wire_format(sensor.name);
    const bool velodyne = family == sensor::WireFamily::Velodyne;
    if (rpm > 0) {
        if (!velodyne)
            throw ConfigError(fmt::format(
                "emulate: --rpm applies to Velodyne sensors; Ouster '{}' spins at the rate of "
                "its lidar mode (<W>x<F>)",
                sensor.name));
        const auto* sp = dynamic_cast<const sensor::SpinningPattern*>(sensor.scan.get());
        if (!sp) no_wire_format(sensor.name);
        sensor::SpinningConfig cfg = sp->config();
        cfg.rotation_hz = rpm / 60.0;
        sensor.scan = std::make_shared<sensor::SpinningPattern>(cfg);
    }
    if (velodyne) {
        const auto mode = velodyne::parse_return_mode(options.return_mode);
        // Last and dual need every echo of a pulse; the packetizer picks from them.
        if (mode != velodyne::ReturnMode::Strongest)
            sensor.receiver.max_returns = std::max(sensor.receiver.max_returns, 8);
        if (options.timestamp_mode != "TIME_FROM_INTERNAL_OSC")
            throw ConfigError(fmt::format(
                "emulate: --timestamp-mode {}: an Ouster setting (Velodyne packets carry µs past "
                "the UTC hour)",
                options.timestamp_mode));
    } else if (!ouster::parse_timestamp_mode(options.timestamp_mode)) {
        throw ConfigError(
            fmt::format("emulate: --timestamp-mode {}: expected TIME_FROM_INTERNAL_OSC, "
                        "TIME_FROM_SYNC_PULSE_IN or TIME_FROM_PTP_1588",
                        options.timestamp_mode));
    } else if (options.return_mode != "strongest") {
        throw ConfigError(fmt::format(
            "emulate: --return-mode {}: the Ouster profiles emulated here are single-return "
            "(strongest)",
            options.return_mode));
    }
}

WireSetup make_wire(const WireContext& ctx, const WireOptions& options, wire::PacketFn sink,
                    const std::string& udp_host) {
    WireSetup w;
    const sensor::SensorModel& sensor = ctx.sensor;
    if (sensor.wire.family == sensor::WireFamily::None) no_wire_format(sensor.name);
    if (sensor.wire.family == sensor::WireFamily::Velodyne) {
        const auto model = velodyne::model_from_name(sensor.wire.model);
        if (!model) no_wire_format(sensor.name);
        const auto& d = velodyne::descriptor(*model);
        const auto mode = velodyne::parse_return_mode(options.return_mode);
        velodyne::PacketizerOptions po;
        po.position_packets = options.position_packets;
        if (options.position_packets) po.position = position_fn(ctx);
        if (!ctx.gps_locked) {
            po.position = [](core::GpsTime) {
                velodyne::GeoFix none;
                none.valid = false;
                return none;
            };
            po.position_options.pps = velodyne::PpsStatus::Absent;
            po.hdl64_gps_status = 0;
        }
        po.clock_step = ctx.clock_step;
        auto p =
            std::make_unique<velodyne::Packetizer>(d, mode, sensor, ctx.start, std::move(sink), po);
        w.packets_per_second = d.packets_per_second(mode);  // firing timing is fixed; rpm is not
        w.packetizer = std::move(p);
        w.vendor = "velodyne";
        w.side_file = velodyne::calibration_yaml(d);
        w.side_file_kind = "calibration";
        w.side_file_ext = ".yaml";
        return w;
    }
    const auto profile = ouster::parse_profile(options.profile);
    const ouster::Descriptor d = ouster::make_descriptor(sensor.wire.model, profile);
    ouster::PacketizerConfig cfg;
    cfg.start = ctx.start;
    const auto clock_mode = ouster::parse_timestamp_mode(options.timestamp_mode);
    if (!clock_mode)
        throw ConfigError("emulate: --timestamp-mode " + options.timestamp_mode + ": unknown");
    cfg.clock.mode = *clock_mode;
    cfg.clock.step = ctx.clock_step;
    const core::Trajectory* traj = &ctx.trajectory;
    const core::Mount mount = ctx.mount;
    if (options.imu_packets)
        cfg.imu = [traj, mount, d](core::GpsTime t) {
            return ouster::imu_reading(*traj, mount, d, t);
        };
    w.packetizer = std::make_unique<ouster::OusterPacketizer>(d, cfg, std::move(sink));
    w.packets_per_second = double(d.mode.hz) * double(d.packets_per_frame());
    w.vendor = "ouster";
    ouster::MetadataOptions mo;
    mo.timestamp_mode = *clock_mode;
    if (!udp_host.empty()) mo.udp_dest = udp_host;
    w.side_file = ouster::metadata_json(d, mo);
    w.side_file_kind = "metadata";
    w.side_file_ext = ".json";
    return w;
}

}  // namespace mirage::wire
