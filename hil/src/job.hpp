// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "mirage/core/trajectory.hpp"
#include "mirage/physics/radiometry.hpp"
#include "mirage/render/embree_renderer.hpp"
#include "mirage/render/pipeline.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/wire/setup.hpp"

// Declared only: CLI11 compiles some 200 functions into every file that includes it, most of such
// a file's build time, and most users of a job never touch the command line.
namespace CLI {
class App;
}  // namespace CLI

namespace mirage::hil {

// Command-line inputs shared by `render`, `demo` and `bench`.
struct JobInputs {
    std::string scene = "demo";
    std::string sensor = "vlp16";
    std::string trajectory;  // CSV path, static:x,y,z[,roll,pitch,yaw], demo-car, demo-flight
    std::string interpolation = "cubic";  // trajectory positions: linear | cubic
    std::string duration;  // seconds (decimal, exact); empty = trajectory span (or 1 s)
    std::string start;     // UTC/GPS time of pulse 0; empty = trajectory start
    std::uint64_t seed = 1;
    int threads = 0;
    int sub_rays = 0;       // 0 = the sensor's own
    std::string footprint;  // sampled | adaptive; empty = the sensor's own
    int max_returns = 0;    // 0 = the sensor's own
    bool no_noise = false;
    std::string quality = "medium";  // BVH: low | medium | high
    double visibility_km = 23.0;
    double extinction_per_km = -1;  // overrides visibility when ≥ 0
    double lidar_ratio_sr = 0;      // > 0: the atmosphere's volume backscatter in waveforms
    double scale_height_km = 0;     // > 0: α(z) = α·exp(−z/H) above the scene's z = 0
    std::string cn2;                // turbulence: Cn² in m^(−2/3), or hv57; empty: none
    double sun_elevation_deg = 45.0;
    double sun_azimuth_deg = 180.0;
    double solar_irradiance = 700.0;  // W/(m²·µm) normal to the sun
    std::vector<double> lever_arm;    // x,y,z m
    std::vector<double> boresight;    // roll,pitch,yaw deg
    // Re-simulation from a recorded navigation log instead of --trajectory (nav_log.hpp).
    std::string nav_log;
    std::string nav_protocol = "nmea";
    std::string nav_origin;  // lat,lon,h: tangent-plane frame; empty = the scene's georef
    double nav_undulation_m = 0;
    std::string nav_date;  // NMEA logs without RMC/ZDA: YYYY-MM-DD
};

void add_job_options(CLI::App& app, JobInputs& in, bool with_sensor_and_trajectory = true);

// "gps:<seconds>.<ns>" of the host's clock now, whole ms: a live fake sensor stamps the present.
std::string gps_now_spec();

// demo-car, demo-flight, demo-camouflage: trajectories of the demo town (--scene demo only).
bool is_demo_trajectory(const std::string& spec);

// Owns what a render needs; setup() hands it to render::render() and the other renderers.
struct Job {
    std::shared_ptr<const scene::Scene> scene;  // shared: renderers keep pointers into it
    sensor::SensorModel sensor;
    core::Trajectory trajectory = core::Trajectory::fixed({});
    core::Mount mount;
    physics::Environment env;
    render::RenderOptions options;
    std::shared_ptr<const render::EmbreeRenderer> renderer;  // shared by jobs on one scene
    double scene_seconds = 0;

    // Refers to the job's scene, renderer (which must be set), sensor and trajectory.
    render::Setup setup() const;
};

// Loads scene, sensor and trajectory, builds the BVH. Throws ConfigError on bad inputs.
Job load_job(const JobInputs& in, bool build_renderer = true);
// Same with a scene already loaded (moved into the job).
Job load_job_with_scene(const JobInputs& in, std::shared_ptr<const scene::Scene> scene,
                        double scene_seconds, bool build_renderer = true);
std::shared_ptr<const scene::Scene> load_scene_timed(const std::string& spec, double& seconds);
// Exact decimal seconds -> ns ("1.5" -> 1'500'000'000); throws ConfigError naming `what`.
core::Nanos parse_seconds(const std::string& text, const std::string& what);
// Lets the render workers finish chunks up to `lead` of firing time ahead of the one being
// written (RenderOptions::window_chunks); call after the sensor is final.
void set_render_lead(Job& job, core::Nanos lead);
render::EmbreeOptions embree_options(const std::string& quality);
// What the job's packets describe besides the returns (the job must outlive the packetizer).
wire::WireContext wire_context(const Job& job);

// The host's GPS time (CLOCK_REALTIME through the leap-second table) as an offset from
// CLOCK_MONOTONIC: monotonic = GPS + offset (docs/time.md §1).
std::int64_t host_gps_offset_ns();
// How far ahead of the host's clock a job started "now" fires its first pulse: loading is done,
// the renderers fill their lead meanwhile.
inline constexpr core::Nanos kHostClockStartLead{500'000'000};
// The host's GPS time `ahead` from now, whole ms.
core::GpsTime host_gps_time_ahead(core::Nanos ahead);
// Moves a job's first pulse to `start`, and a trajectory generated from its old start with it
// (demo trajectories; a static pose has no times): a job that starts "now" is moved, once it is
// loaded, to a moment its packets can keep on the host's CLOCK_REALTIME (docs/time.md §1).
void move_start(Job& job, core::GpsTime start);

}  // namespace mirage::hil
