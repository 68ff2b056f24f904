// SPDX-License-Identifier: Apache-2.0
#include "rig_plan.hpp"

#include <fmt/format.h>

#include <chrono>

#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/navio/dis_uri.hpp"
#include "mirage/navproto/protocol.hpp"
#include "mirage/output/packet_output.hpp"

namespace mirage::hil {
namespace {

std::unique_ptr<RigSensor> plan_sensor(const rig::SensorEntry& e, const JobInputs& common,
                                       const std::shared_ptr<const scene::Scene>& scene,
                                       double scene_s, const RigPlan& plan, const RigPlan* reuse) {
    auto r = std::make_unique<RigSensor>();
    r->entry = e;
    JobInputs in = common;
    in.sensor = e.sensor;
    in.lever_arm.assign(e.lever_arm.begin(), e.lever_arm.end());
    in.boresight.assign(e.boresight.begin(), e.boresight.end());
    const RigPlan& owner = plan.sensors.empty() && reuse ? *reuse : plan;
    r->job = load_job_with_scene(in, scene, scene_s, owner.sensors.empty());
    if (!owner.sensors.empty()) r->job.renderer = owner.sensors.front()->job.renderer;  // one BVH
    r->wire.return_mode = e.return_mode;
    r->wire.profile = e.profile;
    r->wire.timestamp_mode = e.timestamp_mode;
    wire::prepare_sensor(r->job.sensor, r->wire, e.rpm);
    set_render_lead(r->job, output::kEmulateRenderLead);
    const bool ouster = r->job.sensor.wire.family == sensor::WireFamily::Ouster;
    r->ports = output::sensor_ports(ouster, e.ports.data, e.ports.position, e.ports.imu);
    r->wire.position_packets = r->ports.position != 0;
    r->wire.imu_packets = r->ports.imu != 0;
    // The encoder checks the model's settings (rpm range, profile); its packets go nowhere here.
    const wire::WireSetup w = wire::make_wire(
        wire_context(r->job), r->wire, [](const wire::PacketView&) {}, e.to);
    r->vendor = w.vendor;
    r->packets_per_second = w.packets_per_second;
    return r;
}

// What the rig file names but the parser cannot judge alone: the duration as exact seconds, the
// start time, and a live source's URI (its protocol and, for DIS, its options). Errors name the
// rig file and the key.
void check_run_settings(const rig::RigConfig& c, const std::string& duration, RigPlan& plan) {
    const auto named = [&](const std::string& key, const auto& f) {
        try {
            f();
        } catch (const ConfigError& e) {
            throw ConfigError(fmt::format("rig '{}': {}: {}", c.file, key, e.what()));
        }
    };
    if (!duration.empty())
        named("duration", [&] { plan.live_duration_ns = parse_seconds(duration, "duration"); });
    if (!c.start.empty() && c.start != "now")
        named("start", [&] { (void)core::parse_time(c.start); });
    if (c.nav.empty()) return;
    named("navigation.nav", [&] {
        const navproto::NavUri uri = navproto::parse_nav_uri(c.nav);
        std::string udp;
        if (uri.protocol == navproto::NavProtocol::Dis)
            (void)navio::parse_dis_transport(uri.transport, udp);
    });
}

}  // namespace

RigPlan plan_rig(const rig::RigConfig& config, const std::string& duration_override,
                 const RigPlan* reuse) {
    if (reuse && reuse->sensors.empty()) reuse = nullptr;
    RigPlan plan;
    plan.config = config;
    // A live source: the pose comes later; the job's trajectory and duration are stand-ins.
    const bool live = !config.nav.empty();
    const std::string& duration = duration_override.empty() ? config.duration : duration_override;
    if (live) plan.live_duration = duration;
    check_run_settings(config, duration, plan);
    JobInputs common;
    common.trajectory = live ? std::string("static:0,0,0") : config.trajectory;
    if (!config.nav_log.empty()) {  // re-simulated from the log, on its own times
        common.nav_log = config.nav_log;
        common.nav_protocol = config.nav_log_protocol;
        if (!config.nav_origin.empty())
            common.nav_origin = fmt::format("{},{},{}", config.nav_origin[0], config.nav_origin[1],
                                            config.nav_origin[2]);
    }
    common.duration = live ? std::string("1") : duration;
    if (!live) common.start = config.start;
    common.threads = config.threads;
    const bool is_static = !live && common.trajectory.starts_with("static:");
    plan.forever = is_static && common.duration.empty();
    if (plan.forever) common.duration = "86400";  // until interrupted (a day at most)
    // One start for every sensor: now for demo trajectories and static poses (and when asked);
    // a trajectory file's own start otherwise.
    if (common.start == "now" ||
        (common.start.empty() && (is_static || is_demo_trajectory(common.trajectory)))) {
        common.start = gps_now_spec();
        plan.start_now = !live;
    }
    double scene_s = reuse ? reuse->sensors.front()->job.scene_seconds : 0;
    const auto scene =
        reuse ? reuse->sensors.front()->job.scene : load_scene_timed(config.scene, scene_s);
    for (std::size_t i = 0; i < config.sensors.size(); ++i) {
        const rig::SensorEntry& e = config.sensors[i];
        try {
            plan.sensors.push_back(plan_sensor(e, common, scene, scene_s, plan, reuse));
        } catch (const ConfigError& err) {
            throw ConfigError(fmt::format("rig '{}': sensors[{}] ('{}', line {}): {}", config.file,
                                          i, e.name, e.line, err.what()));
        }
    }
    return plan;
}

namespace {

// "drop 1 % in bursts of 3, range bias 0.5 m, …"; empty without faults.
std::string faults_text(const rig::Faults& f) {
    std::string s;
    const auto add = [&s](const std::string& t) { s += (s.empty() ? "" : ", ") + t; };
    if (f.drop_rate > 0)
        add(fmt::format("drop {:g} % in bursts of {}", 100 * f.drop_rate, f.drop_burst));
    if (f.range_bias_m != 0) add(fmt::format("range bias {:g} m", f.range_bias_m));
    if (f.range_noise_m != 0) add(fmt::format("range noise {:g} m", f.range_noise_m));
    if (f.stale_nav) add("stale navigation");
    if (f.freeze_nav) add("frozen navigation");
    if (f.stop) add("stopped");
    return s;
}

std::string control_text(const rig::Control& k) {
    std::string s = fmt::format("  control: modbus tcp {}", k.tcp);
    if (!k.rtu.empty())
        s += fmt::format(", rtu {} {} baud parity {} stop bits {} unit {}", k.rtu, k.baud, k.parity,
                         k.stop_bits, k.unit);
    s += fmt::format(", up to {} clients, watchdog {}; waits idle for arm and start\n",
                     k.max_clients,
                     k.watchdog_ms ? fmt::format("{} ms", k.watchdog_ms) : std::string("off"));
    for (std::size_t i = 0; i < k.scenarios.size(); ++i) {
        const rig::Scenario& x = k.scenarios[i];
        s += fmt::format("    scenario {}: {}{}{}{}\n", i, x.name,
                         x.trajectory.empty() ? "" : ", trajectory " + x.trajectory,
                         x.start.empty() ? "" : ", start " + x.start,
                         x.duration.empty() ? "" : ", " + x.duration + " s");
    }
    return s;
}

}  // namespace

std::string describe(const RigPlan& plan) {
    const rig::RigConfig& c = plan.config;
    const Job& first = plan.sensors.front()->job;
    const std::string nav =
        c.nav.empty()
            ? fmt::format("{} {}, first pulse gps:{:.3f}",
                          c.nav_log.empty() ? "trajectory" : c.nav_log_protocol + " log",
                          c.nav_log.empty() ? c.trajectory : c.nav_log,
                          double(first.options.start.time_since_epoch().count()) / 1e9)
            : fmt::format("navigation {} (max extrapolation {} ms)", c.nav, c.max_extrapolation_ms);
    const bool until_stopped = plan.forever || (!c.nav.empty() && plan.live_duration.empty());
    const std::string span =
        until_stopped   ? std::string("until Ctrl-C")
        : c.nav.empty() ? fmt::format("{:.3f} s", double(first.options.duration.count()) / 1e9)
                        : fmt::format("{} s", plan.live_duration);
    std::string s = fmt::format("rig '{}': scene {}, {}, {}, {} render thread(s) per sensor\n",
                                c.file, c.scene, nav, span, c.threads);
    double total = 0;
    for (const auto& r : plan.sensors) {
        const rig::SensorEntry& e = r->entry;
        total += r->packets_per_second;
        s += fmt::format(
            "  {}: {} {} ({}), {:.1f} data packets/s; lever arm [{}, {}, {}] m, boresight [{}, "
            "{}, {}] deg\n    -> {}{}{}{}{}\n",
            e.name, r->vendor, r->job.sensor.name,
            r->vendor == "ouster" ? "profile " + e.profile + ", " + e.timestamp_mode
                                  : "return mode " + e.return_mode,
            r->packets_per_second, e.lever_arm[0], e.lever_arm[1], e.lever_arm[2], e.boresight[0],
            e.boresight[1], e.boresight[2],
            e.to.empty() ? "(no network)" : fmt::format("{}: data {}", e.to, r->ports.data),
            e.to.empty() || r->ports.position == 0
                ? ""
                : fmt::format(", position {}", r->ports.position),
            e.to.empty() || r->ports.imu == 0 ? "" : fmt::format(", imu {}", r->ports.imu),
            e.source_port ? fmt::format(", from port {}", e.source_port) : "",
            (e.pcap.empty() ? "" : ", pcap " + e.pcap) + (e.las.empty() ? "" : ", las " + e.las));
        const std::string f = faults_text(e.faults ? *e.faults : c.faults);
        if (!f.empty()) s += "    faults: " + f + "\n";
    }
    s += fmt::format("  {} sensors, {:.1f} data packets/s in all\n", plan.sensors.size(), total);
    if (c.control.enabled) s += control_text(c.control);
    return s;
}

}  // namespace mirage::hil
