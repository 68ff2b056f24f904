// SPDX-License-Identifier: Apache-2.0
#include "rig_control.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <thread>

#include "mirage/control/modbus_server.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "rig_plan.hpp"
#include "rig_run.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {
namespace {

// FNV-1a over the rig file's bytes: a controller checks it loaded the rig it expects.
std::uint64_t file_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (std::istreambuf_iterator<char> it(in), end; it != end; ++it) {
        h ^= static_cast<unsigned char>(*it);
        h *= 0x100000001b3ull;
    }
    return h;
}

control::ControlEndpoint endpoint(const rig::Control& k) {
    control::ControlEndpoint e;
    if (k.tcp == "off")
        e.tcp_port = -1;
    else
        control::parse_tcp_address(k.tcp, e);
    e.max_clients = k.max_clients;
    e.rtu_device = k.rtu;
    e.baud = k.baud;
    e.parity = k.parity;
    e.stop_bits = k.stop_bits;
    e.unit = k.unit;
    return e;
}

// The rig file with scenario `i`'s changes (scenario 0 of a rig without a list: as written).
rig::RigConfig scenario_config(const rig::RigConfig& c, std::size_t i) {
    rig::RigConfig s = c;
    if (i >= c.control.scenarios.size()) return s;
    const rig::Scenario& x = c.control.scenarios[i];
    if (!x.trajectory.empty()) s.trajectory = x.trajectory;
    if (!x.start.empty()) s.start = x.start;
    if (!x.duration.empty()) s.duration = x.duration;
    return s;
}

// One run of the rig on its own thread; `stop` ends it early. `id`: the model's run number.
struct ActiveRun {
    std::uint64_t id = 0;
    std::atomic<bool> stop{false}, done{false};
    std::string error;
    bool nav_lost = false;
    std::thread thread;
};

// `base`: the plan whose scene and BVH the run shares.
void start_run(ActiveRun& a, const rig::RigConfig& config, const RigPlan& base,
               std::size_t scenario, const RigControlOptions& o, const control::ControlModel& model,
               RigView& view) {
    a.thread = std::thread([&a, &config, &base, scenario, &o, &model, &view] {
        try {
            RigPlan plan = plan_rig(scenario_config(config, scenario), o.duration_override, &base);
            RigRunOptions ro;
            ro.status_line = o.status_line;
            ro.rt_priority = o.rt_priority;
            ro.awake = o.awake;
            ro.stop = &a.stop;
            ro.control = &model;
            ro.view = &view;
            std::fprintf(stderr, "mirage rig: control: run %llu, scenario %zu\n",
                         static_cast<unsigned long long>(a.id), scenario);
            if (plan.config.nav.empty())
                run_rig(plan, ro);
            else
                run_rig_live(plan, ro);
        } catch (const FirstPoseTimeout& e) {
            a.error = e.what();
            a.nav_lost = true;
            std::fprintf(stderr, "mirage rig: control: run failed: %s\n", e.what());
        } catch (const std::exception& e) {
            a.error = e.what();
            std::fprintf(stderr, "mirage rig: control: run failed: %s\n", e.what());
        }
        a.done = true;
    });
}

control::Identity identity(const rig::RigConfig& c) {
    control::Identity id;
    id.version[0] = MIRAGE_VERSION_MAJOR;
    id.version[1] = MIRAGE_VERSION_MINOR;
    id.version[2] = MIRAGE_VERSION_PATCH;
    id.rig_hash = file_hash(c.file);
    id.scenarios = static_cast<std::uint16_t>(std::max<std::size_t>(c.control.scenarios.size(), 1));
    id.sensors = c.sensors.size();
    id.can_freeze_nav = !c.nav.empty();
    return id;
}

}  // namespace

void run_controlled_rig(const rig::RigConfig& config, const RigControlOptions& o) {
    if (config.sensors.size() > control::kMaxSensors)
        throw ConfigError(fmt::format("rig '{}': control: at most {} sensors under a control plane",
                                      config.file, control::kMaxSensors));
    // Every scenario planned now, so a bad one is refused at load rather than at its start; the
    // scene and BVH are loaded once and shared by every run.
    const RigPlan base = plan_rig(scenario_config(config, 0), o.duration_override);
    for (std::size_t i = 1; i < config.control.scenarios.size(); ++i)
        (void)plan_rig(scenario_config(config, i), o.duration_override, &base);
    control::ControlModel model(identity(config), rig_fault_defaults(config),
                                static_cast<std::uint16_t>(config.control.watchdog_ms));
    RigView view;
    control::ModbusServer server(endpoint(config.control), model,
                                 [&view] { return view.status(); });
    server.start();
    std::fprintf(
        stderr,
        "mirage rig: control plane: modbus tcp %s, rtu %s; state idle — write 1 (arm) "
        "then 2 (start) to holding register 0 (docs/control.md)\n",
        server.tcp_port() >= 0
            ? fmt::format("{}:{}", endpoint(config.control).tcp_host, server.tcp_port()).c_str()
            : "off",
        config.control.rtu.empty() ? "off" : config.control.rtu.c_str());
    const auto& sig = install_stop_signal();
    std::unique_ptr<ActiveRun> run;
    const auto finish = [&] {
        run->thread.join();
        if (!run->error.empty())
            model.fault(run->id, run->nav_lost ? control::ErrorCode::NavigationLost
                                               : control::ErrorCode::SensorFailed);
        else
            model.run_ended(run->id);
        run.reset();
    };
    while (!sig.load()) {
        model.tick(hostclock::monotonic_ns());
        const control::ControlModel::Order order = model.order();
        const bool wanted = order.state == control::RigState::Running;
        // Stop, reset, the watchdog's safe state, a newer start, or a failed sensor (the rest of
        // the rig stops with it: fault is the safe state) end the run; so does its own end.
        if (run && (!wanted || run->id != order.run || view.sensor_failed())) {
            run->stop = true;  // each sensor drops its queue at its next packet (rig_run.cpp send)
            finish();
        } else if (run && run->done.load()) {
            finish();
        } else if (!run && wanted) {  // a finished run is stopped or faulted: never restarted
            run = std::make_unique<ActiveRun>();
            run->id = order.run;
            start_run(*run, config, base, order.scenario, o, model, view);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (run) {
        run->stop = true;
        finish();
    }
    server.stop();
    const control::ServerCounters sc = server.counters();
    std::printf(
        "mirage rig: control: %llu runs; %llu connections (%llu refused, %llu closed malformed, "
        "%llu idle, %llu not reading); %llu replies, %llu internal errors; serial frame errors "
        "%llu, reopens %llu\n",
        static_cast<unsigned long long>(model.runs()),
        static_cast<unsigned long long>(sc.connections),
        static_cast<unsigned long long>(sc.refused_connections),
        static_cast<unsigned long long>(sc.closed_malformed),
        static_cast<unsigned long long>(sc.closed_idle),
        static_cast<unsigned long long>(sc.closed_unread),
        static_cast<unsigned long long>(sc.replies),
        static_cast<unsigned long long>(sc.internal_errors),
        static_cast<unsigned long long>(sc.frame_errors),
        static_cast<unsigned long long>(sc.rtu_reopens));
}

}  // namespace mirage::hil
