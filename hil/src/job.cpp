// SPDX-License-Identifier: Apache-2.0
#include "job.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navproto/nav_log_resim.hpp"
#include "mirage/scene/demo_town.hpp"
#include "mirage/scene/loader.hpp"

namespace mirage::hil {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<double> split_numbers(const std::string& text, const std::string& what) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            const double v = std::stod(item, &used);
            if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
            out.push_back(v);
        } catch (const std::exception&) {
            throw ConfigError(fmt::format("{}: '{}' is not a number", what, item));
        }
    }
    return out;
}

// --cn2: empty (none), hv57, or one Cn² in [0, 1e-10] m^(−2/3) (beyond, weak-turbulence theory
// and this model have long failed).
physics::Turbulence turbulence_of(const std::string& text) {
    physics::Turbulence t;
    if (text.empty()) return t;
    if (text == "hv57") {
        t.hufnagel_valley = true;
        return t;
    }
    const std::vector<double> v = split_numbers(text, "--cn2");
    if (v.size() != 1 || v[0] < 0 || v[0] > 1e-10)
        throw ConfigError("--cn2: '" + text + "' is not hv57 or one Cn² in [0, 1e-10] m^(-2/3)");
    t.cn2 = v[0];
    return t;
}

bool is_demo_scene(const std::string& spec) {
    return spec == "demo" || spec.rfind("demo:", 0) == 0;
}

scene::DemoTownOptions demo_options(const std::string& spec) {
    scene::DemoTownOptions o;
    if (spec.rfind("demo:", 0) == 0) o.seed = std::stoull(spec.substr(5));
    return o;
}

}  // namespace

std::string gps_now_spec() {
    const auto unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
    const std::int64_t gps_ns =
        core::gps_from_unix_ns(unix_ns / 1'000'000 * 1'000'000).time_since_epoch().count();
    return fmt::format("gps:{}.{:09d}", gps_ns / 1'000'000'000, gps_ns % 1'000'000'000);
}

std::int64_t host_gps_offset_ns() {
    // Bracketed: a thread preempted between two plain reads would skew the anchor (and fake a
    // step to the ClockStepFollower) by the length of the preemption.
    const std::int64_t rt_minus_mono = hostclock::realtime_minus_monotonic();
    const std::int64_t mono = hostclock::monotonic_ns();
    return mono - core::gps_from_unix_ns(mono + rt_minus_mono).time_since_epoch().count();
}

core::GpsTime host_gps_time_ahead(core::Nanos ahead) {
    const std::int64_t gps = hostclock::monotonic_ns() - host_gps_offset_ns() + ahead.count();
    return core::GpsTime(core::Nanos(gps / 1'000'000 * 1'000'000));
}

void move_start(Job& job, core::GpsTime start) {
    const core::Nanos shift = start - job.options.start;
    job.options.start = start;
    if (job.trajectory.is_fixed()) return;
    std::vector<core::StampedPose> samples = job.trajectory.samples();
    for (auto& s : samples) s.t += shift;
    job.trajectory = core::Trajectory(std::move(samples), job.trajectory.interpolation());
}

bool is_demo_trajectory(const std::string& spec) {
    return spec == "demo-car" || spec == "demo-flight" || spec == "demo-camouflage";
}

render::Setup Job::setup() const {
    if (!renderer) throw std::logic_error("Job::setup: no renderer built");
    return {*scene, *renderer, sensor, trajectory, mount, env, options};
}

wire::WireContext wire_context(const Job& job) {
    return {job.sensor, *job.scene, job.trajectory, job.mount, job.options.start};
}

void set_render_lead(Job& job, core::Nanos lead) {
    job.options.window_chunks = render::chunks_for_lead(job.sensor, job.options.chunk_pulses, lead);
}

core::Nanos parse_seconds(const std::string& text, const std::string& what) {
    // Exact decimal digits to ns (no float seconds); negative durations make no sense here.
    const auto ns = core::parse_decimal_seconds(text);
    if (!ns || ns->count() < 0)
        throw ConfigError(fmt::format("{}: '{}' is not a number of seconds", what, text));
    return *ns;
}

render::EmbreeOptions embree_options(const std::string& quality) {
    render::EmbreeOptions o;
    if (quality == "low")
        o.quality = render::BvhQuality::Low;
    else if (quality == "medium")
        o.quality = render::BvhQuality::Medium;
    else if (quality == "high")
        o.quality = render::BvhQuality::High;
    else
        throw ConfigError(fmt::format("--quality: '{}' is not low, medium or high", quality));
    return o;
}

void add_job_options(CLI::App& app, JobInputs& in, bool with_sensor_and_trajectory) {
    app.add_option("--scene", in.scene, "Scene YAML, or 'demo' / 'demo:<seed>' for the demo town")
        ->capture_default_str();
    if (with_sensor_and_trajectory) {
        app.add_option("--sensor", in.sensor,
                       "Sensor preset name (see `mirage sensors`) or YAML file")
            ->capture_default_str();
        app.add_option("--trajectory", in.trajectory,
                       "Trajectory CSV, 'static:x,y,z[,roll,pitch,yaw]' (local m, deg), "
                       "'demo-car', 'demo-flight' or 'demo-camouflage'");
        app.add_option("--interpolation", in.interpolation,
                       "Trajectory positions between samples: linear or cubic (attitude: slerp)")
            ->check(CLI::IsMember({"linear", "cubic"}))
            ->capture_default_str();
        app.add_option("--nav-log", in.nav_log,
                       "Re-simulate a recorded navigation log instead of --trajectory (raw "
                       "NMEA/NovAtel/NCOM bytes, candump -L for CAN); time = the INS GPS time");
        app.add_option("--nav-protocol", in.nav_protocol,
                       "--nav-log protocol: nmea, novatel, ncom, oxts-can or sbg-can")
            ->capture_default_str();
        app.add_option("--nav-origin", in.nav_origin,
                       "--nav-log: local frame = tangent plane at lat,lon,h (deg, deg, m); "
                       "default: the scene's UTM/UPS georeference");
        app.add_option("--nav-undulation", in.nav_undulation_m,
                       "--nav-log: geoid undulation (m) added to heights the INS gives above MSL")
            ->capture_default_str();
        app.add_option("--nav-date", in.nav_date,
                       "--nav-log, NMEA without RMC/ZDA: the log's UTC date YYYY-MM-DD");
        app.add_option("--duration", in.duration, "Seconds to render (default: trajectory span)");
        app.add_option("--start", in.start,
                       "Time of the first pulse: UTC ISO 8601 or gps:<seconds>");
    }
    app.add_option("--seed", in.seed, "Random seed (output is identical for a seed)")
        ->capture_default_str();
    app.add_option("--threads", in.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    app.add_option("--sub-rays", in.sub_rays,
                   "Footprint sub-rays per pulse: 1, 7, 19, 37 (0 = sensor's)");
    app.add_option("--footprint", in.footprint,
                   "sampled: trace every sub-ray; adaptive: probes first, a footprint on one plane "
                   "in closed form (default: the sensor's beam.footprint)")
        ->check(CLI::IsMember({"sampled", "adaptive"}));
    app.add_option("--max-returns", in.max_returns, "Returns kept per pulse, 1-8 (0 = sensor's)")
        ->check(CLI::Range(0, sensor::kMaxReturns));
    app.add_flag("--no-noise", in.no_noise, "Disable range noise, jitter and detector noise");
    app.add_option("--quality", in.quality, "BVH build quality: low, medium, high")
        ->capture_default_str();
    app.add_option("--visibility-km", in.visibility_km,
                   "Meteorological visibility (Kim/Kruse extinction)")
        ->capture_default_str();
    app.add_option("--extinction-per-km", in.extinction_per_km,
                   "Extinction coefficient α, overrides visibility");
    app.add_option("--extinction-scale-height-km", in.scale_height_km,
                   "Extinction falls as exp(−z/H) above the scene's z = 0, where visibility or "
                   "--extinction-per-km give it (aerosols ~1.2, molecules ~8); 0: homogeneous")
        ->check(CLI::Range(0.0, 1e3))
        ->capture_default_str();
    app.add_option("--lidar-ratio", in.lidar_ratio_sr,
                   "Extinction-to-backscatter ratio S (sr) of the air: > 0 puts its volume "
                   "backscatter β = α/S into waveforms (fog ~20, haze ~50; linear detector)")
        ->check(CLI::Range(0.0, 1e4))
        ->capture_default_str();
    app.add_option("--cn2", in.cn2,
                   "Turbulence: Cn² in m^(-2/3) along every path (1e-15 weak … 1e-13 strong), or "
                   "hv57 for the Hufnagel-Valley 5/7 profile by height above z = 0; each pulse's "
                   "spot spreads, and with noise on its beam and its image wander");
    app.add_option("--sun-elevation-deg", in.sun_elevation_deg,
                   "Sun elevation; ≤ 0 is night (no background)")
        ->capture_default_str();
    app.add_option("--sun-azimuth-deg", in.sun_azimuth_deg, "Sun azimuth, clockwise from north")
        ->capture_default_str();
    app.add_option("--solar-irradiance", in.solar_irradiance,
                   "Solar spectral irradiance W/(m²·µm) at the laser line")
        ->capture_default_str();
    app.add_option("--lever-arm", in.lever_arm, "Sensor position in the platform frame: x,y,z m")
        ->delimiter(',')
        ->expected(3);
    app.add_option("--boresight", in.boresight,
                   "Sensor attitude in the platform frame: roll,pitch,yaw deg")
        ->delimiter(',')
        ->expected(3);
}

std::shared_ptr<const scene::Scene> load_scene_timed(const std::string& spec, double& seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    auto s = std::make_shared<const scene::Scene>(scene::resolve_scene(spec));
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "scene '%s': %s\n", spec.c_str(), scene::describe(*s).c_str());
    return s;
}

namespace {

// Every trajectory sample's sensor position within core::kLocalRangeM of the scene's anchor.
void check_anchor_range(const Job& job) {
    for (const core::StampedPose& s : job.trajectory.samples()) {
        const Eigen::Vector3d p = (s.pose * job.mount.as_pose()).position;
        if (p.cwiseAbs().maxCoeff() < core::kLocalRangeM) continue;  // false for NaN too
        throw ConfigError(fmt::format(
            "trajectory: the sensor at ({:.1f}, {:.1f}, {:.1f}) m from the scene's anchor is "
            "beyond ±{:.0f} m on an axis, where float32 steps exceed 1 mm (docs/conventions.md "
            "§3): a trajectory in another frame than the scene's?",
            p.x(), p.y(), p.z(), core::kLocalRangeM));
    }
}

}  // namespace

Job load_job(const JobInputs& in, bool build_renderer) {
    double seconds = 0;
    auto scene = load_scene_timed(in.scene, seconds);  // before reading `seconds`
    return load_job_with_scene(in, std::move(scene), seconds, build_renderer);
}

Job load_job_with_scene(const JobInputs& in, std::shared_ptr<const scene::Scene> scene,
                        double scene_seconds, bool build_renderer) {
    Job job;
    job.scene = std::move(scene);
    job.scene_seconds = scene_seconds;
    job.sensor = sensor::resolve_sensor(in.sensor);
    if (in.sub_rays > 0) {
        (void)sensor::footprint(in.sub_rays, job.sensor.beam.profile,
                                job.sensor.beam.divergence_rad);
        job.sensor.beam.sub_rays = in.sub_rays;
    }
    if (!in.footprint.empty()) job.sensor.beam.adaptive_footprint = in.footprint == "adaptive";
    if (in.max_returns > 0) job.sensor.receiver.max_returns = in.max_returns;

    // Time of the first pulse and how long to render.
    core::GpsTime start = core::parse_time("2024-01-01T00:00:00Z");
    const std::string& tspec = in.trajectory;
    core::Nanos span{0};
    const core::Nanos requested =
        in.duration.empty() ? core::Nanos(0) : parse_seconds(in.duration, "--duration");
    if (!in.start.empty()) start = core::parse_time(in.start);
    if (!in.nav_log.empty()) {
        if (!tspec.empty())
            throw ConfigError("--nav-log: give --trajectory or --nav-log, not both");
        job.trajectory = navproto::resimulate_nav_log(
            {in.nav_log, in.nav_protocol, in.nav_origin, in.nav_date, in.nav_undulation_m,
             in.interpolation == "linear" ? core::Interpolation::Linear
                                          : core::Interpolation::Cubic},
            job.scene->georef, stderr);
        if (in.start.empty()) start = job.trajectory.begin();
        span = job.trajectory.end() - start;
    } else if (tspec.empty() || tspec.rfind("static:", 0) == 0) {
        core::Pose pose;
        if (!tspec.empty()) {
            const auto v = split_numbers(tspec.substr(7), "--trajectory static");
            if (v.size() != 3 && v.size() != 6)
                throw ConfigError("--trajectory static: expected x,y,z or x,y,z,roll,pitch,yaw");
            pose.position = {v[0], v[1], v[2]};
            if (v.size() == 6)
                pose.attitude = core::quaternion_from_rpy(v[3] * kDeg, v[4] * kDeg, v[5] * kDeg);
        }
        job.trajectory = core::Trajectory::fixed(pose);
        span = std::chrono::seconds(1);
    } else if (is_demo_trajectory(tspec)) {
        if (!is_demo_scene(in.scene))
            throw ConfigError(fmt::format("--trajectory {}: only valid with --scene demo", tspec));
        const core::Nanos d =
            requested.count() > 0 ? requested : core::Nanos(std::chrono::seconds(10));
        const scene::DemoTownOptions town = demo_options(in.scene);
        job.trajectory = tspec == "demo-car" ? scene::demo_car_trajectory(town, start, d)
                         : tspec == "demo-flight"
                             ? scene::demo_flight_trajectory(town, start, d)
                             : scene::demo_camouflage_trajectory(town, start, d);
        span = d;
    } else {
        job.trajectory =
            core::load_trajectory_csv(tspec, job.scene->georef,
                                      in.interpolation == "linear" ? core::Interpolation::Linear
                                                                   : core::Interpolation::Cubic);
        if (in.start.empty()) start = job.trajectory.begin();
        span = job.trajectory.end() - start;
    }
    job.options.start = start;
    job.options.duration = requested.count() > 0 ? requested : span;
    if (job.options.duration.count() <= 0)
        throw ConfigError(
            "--duration: nothing to render (duration is zero or the trajectory has one sample)");
    job.options.seed = in.seed;
    job.options.threads = in.threads;
    job.options.noise = !in.no_noise;

    if (in.lever_arm.size() == 3)
        job.mount.lever_arm_m = {in.lever_arm[0], in.lever_arm[1], in.lever_arm[2]};
    if (in.boresight.size() == 3)
        job.mount.boresight = core::quaternion_from_rpy(
            in.boresight[0] * kDeg, in.boresight[1] * kDeg, in.boresight[2] * kDeg);
    check_anchor_range(job);
    job.env.atmosphere.extinction_per_m =
        in.extinction_per_km >= 0 ? in.extinction_per_km / 1000.0
                                  : physics::Atmosphere::extinction_from_visibility(
                                        in.visibility_km * 1000.0, job.sensor.beam.wavelength_m);
    job.env.lidar_ratio_sr = in.lidar_ratio_sr;
    job.env.atmosphere.scale_height_m = in.scale_height_km * 1e3;
    job.env.turbulence = turbulence_of(in.cn2);
    job.env.sun.elevation_rad = in.sun_elevation_deg * kDeg;
    job.env.sun.azimuth_rad = in.sun_azimuth_deg * kDeg;
    job.env.sun.irradiance_w_m2_um = in.solar_irradiance;
    if (build_renderer)
        job.renderer =
            std::make_shared<render::EmbreeRenderer>(*job.scene, embree_options(in.quality));
    return job;
}

}  // namespace mirage::hil
