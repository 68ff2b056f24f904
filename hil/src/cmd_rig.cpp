// SPDX-License-Identifier: Apache-2.0
// `mirage rig FILE`: a vehicle's lidars from one rig file (docs/rig.md) — every sensor rendered
// and paced in one process from one trajectory on one sensor clock: all outputs are anchored to
// the same first-pulse time at the same host instant. `--check` prints the effective
// configuration and opens nothing.
#include <fmt/format.h>
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <thread>

#include "commands.hpp"
#include "live_loop.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navio/nav_input.hpp"
#include "mirage/navpose/nav_counters.hpp"
#include "mirage/navproto/protocol.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/output/packetizer_sink.hpp"
#include "mirage/udp/shared_sender.hpp"
#include "rig_plan.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {
namespace {

// From anchoring to the first send: every sensor's renderer starts at once on a few cores, so the
// rig waits longer than one `mirage emulate` (100 ms) before its first packet is due.
constexpr core::Nanos kRigStartLead{500'000'000};
// Live: packets leave this long after their firing time (`mirage live --pipeline-delay-us`).
constexpr core::Nanos kLivePipelineDelay{250'000};

// One sensor of the running rig: its output, encoder and what its thread measured.
struct RigRun {
    RigSensor* sensor = nullptr;
    std::unique_ptr<output::PacketOutput> out;
    wire::WireSetup wire;
    std::atomic<std::uint64_t> packets{0};
    std::unique_ptr<LiveSession> session;  // live navigation: sends through the session
    render::RenderStats stats;
    LiveTotals live;
    output::PacketOutputTotals totals;
    std::string error;
};

std::unique_ptr<RigRun> open_run(RigSensor& s, const std::shared_ptr<udp::SharedSender>& sender) {
    auto r = std::make_unique<RigRun>();
    r->sensor = &s;
    output::PacketOutputOptions po;
    po.realtime = true;
    po.status_line = false;
    po.shared_sender = sender;
    po.pcap_path = s.entry.pcap;
    output::route_streams(po, s.ports, s.entry.to, s.entry.source_port);
    r->out = std::make_unique<output::PacketOutput>(po);
    RigRun* raw = r.get();
    r->wire = wire::make_wire(
        wire_context(s.job), s.wire,
        [raw](const wire::PacketView& p) {
            if (raw->session)
                raw->session->on_packet(p);
            else
                (*raw->out)(p);
            raw->packets.fetch_add(1, std::memory_order_relaxed);
        },
        s.entry.to);
    return r;
}

// "\rrig: roof 1280 pkt/s | fl 754 pkt/s …" once a second until `done`.
void status_loop(const std::vector<std::unique_ptr<RigRun>>& runs, const std::atomic<bool>& done) {
    std::vector<std::uint64_t> last(runs.size(), 0);
    auto next = std::chrono::steady_clock::now();
    while (!done.load()) {
        next += std::chrono::seconds(1);
        while (!done.load() && std::chrono::steady_clock::now() < next)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        std::string line = "\rrig:";
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const std::uint64_t n = runs[i]->packets.load(std::memory_order_relaxed);
            line += fmt::format(" {} {} pkt/s{}", runs[i]->sensor->entry.name, n - last[i],
                                i + 1 < runs.size() ? " |" : "   ");
            last[i] = n;
        }
        std::fputs(line.c_str(), stderr);
        std::fflush(stderr);
    }
    std::fputs("\n", stderr);
}

// "  roof: 3701 packets (79.49 MB), …": what one sensor sent and how late; the render CPU of a
// trajectory run, the stale windows of a live one.
std::string sensor_line(const RigRun& r, double wall_s) {
    const auto& t = r.totals;
    std::string s = fmt::format(
        "  {}: {} packets ({:.2f} MB), {} points; sent {}, failed sends {}, pcap {}; lateness p50 "
        "{:.0f} µs, p99 {:.0f} µs, worst {:.0f} µs, late {}",
        r.sensor->entry.name, t.packets, double(t.bytes) / 1e6,
        r.session ? r.live.points : r.stats.points, t.sent, t.send_failed, t.pcap_packets,
        double(t.p50.count()) / 1e3, double(t.p99.count()) / 1e3,
        double(t.worst_late.count()) / 1e3, t.late);
    if (r.session) {
        s += fmt::format("; windows {}, stale windows {} in {} periods", r.live.windows,
                         r.live.stale_windows, r.live.stale_periods);
    } else {
        const double cpu =
            r.stats.cpu_rays_s + r.stats.cpu_trace_s + r.stats.cpu_shade_s + r.stats.cpu_output_s;
        s += fmt::format("; pipeline CPU {:.2f} s ({:.1f} % of one core)", cpu,
                         wall_s > 0 ? 100 * cpu / wall_s : 0.0);
    }
    if (!r.error.empty()) s += "; FAILED: " + r.error;
    return s + "\n";
}

void print_summary(const std::vector<std::unique_ptr<RigRun>>& runs, double wall_s, double cpu_s,
                   bool interrupted) {
    std::uint64_t late = 0, failed = 0;
    for (const auto& r : runs) {
        std::fputs(sensor_line(*r, wall_s).c_str(), stdout);
        late += r->totals.late;
        failed += r->totals.send_failed;
    }
    std::printf(
        "mirage rig: %zu sensors for %.3f s; process CPU %.2f s (%.0f %% of one core); late "
        "%llu, failed sends %llu%s\n",
        runs.size(), wall_s, cpu_s, wall_s > 0 ? 100 * cpu_s / wall_s : 0.0,
        static_cast<unsigned long long>(late), static_cast<unsigned long long>(failed),
        interrupted ? " (interrupted)" : "");
}

// One deadline-ordered thread sends every sensor's packets: with a pacing thread per sensor
// the senders of a 2-core machine would wake each other late (docs/rig.md §2).
std::shared_ptr<udp::SharedSender> make_sender(int rt_priority) {
    udp::SharedSenderConfig sc;
    sc.fifo_priority = rt_priority;
    auto sender = std::make_shared<udp::SharedSender>(sc);
    if (rt_priority > 0 && !sender->fifo())
        std::fprintf(stderr, "mirage rig: no SCHED_FIFO for the sender (%s)\n",
                     sender->fifo_error().c_str());
    return sender;
}

// Runs `body` for every sensor on its own thread, with the status line, then the summary.
void run_all(std::vector<std::unique_ptr<RigRun>>& runs, bool status, const std::atomic<bool>& stop,
             const std::function<void(RigRun&)>& body) {
    const double cpu0 = hostclock::process_cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    std::vector<std::thread> threads;
    for (auto& r : runs)
        threads.emplace_back([&r, &body] {
            pthread_setname_np(pthread_self(), "mirage-rig");
            try {
                body(*r);
                r->totals = r->out->finish();
            } catch (const std::exception& e) {
                r->error = e.what();
                std::fprintf(stderr, "\nmirage rig: sensor '%s' failed: %s\n",
                             r->sensor->entry.name.c_str(), e.what());
            }
        });
    std::atomic<bool> done{false};
    std::thread status_thread;
    if (status) status_thread = std::thread([&] { status_loop(runs, done); });
    for (auto& t : threads) t.join();
    done = true;
    if (status_thread.joinable()) status_thread.join();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    print_summary(runs, wall, hostclock::process_cpu_seconds() - cpu0, stop.load());
    for (const auto& r : runs)
        if (!r->error.empty())
            throw IoError(fmt::format("rig: sensor '{}': {}", r->sensor->entry.name, r->error));
}

// A trajectory: every output's first pulse at the same host instant (one sensor clock).
void run_rig(RigPlan& plan, bool status, int rt_priority) {
    const auto sender = make_sender(rt_priority);
    std::vector<std::unique_ptr<RigRun>> runs;
    for (auto& s : plan.sensors) runs.push_back(open_run(*s, sender));
    const core::GpsTime t0 = plan.sensors.front()->job.options.start;
    const std::int64_t anchor = hostclock::monotonic_ns() + kRigStartLead.count();
    for (auto& r : runs) r->out->anchor(t0, anchor);
    std::fprintf(stderr, "%s", describe(plan).c_str());
    const auto& stop = install_stop_signal();
    run_all(runs, status, stop, [&stop](RigRun& r) {
        output::PacketizerSink sink(*r.wire.packetizer);
        r.stats = render::render(r.sensor->job.setup(), sink, {}, &stop);
    });
}

// A live source: one reader and pose buffer for all sensors; pulse 0 of every sensor at the same
// INS time, each sensor rendering one packet's pulses as soon as their firing times have passed
// (mirage live's loop), the first one also timing INS messages to packets.
void run_rig_live(RigPlan& plan, bool status, int rt_priority) {
    const rig::RigConfig& c = plan.config;
    navpose::PoseBufferConfig pc;
    pc.max_extrapolation = core::Nanos(static_cast<std::int64_t>(c.max_extrapolation_ms * 1e6));
    navpose::PoseBuffer poses(pc);
    navio::NavInput nav(navproto::parse_nav_uri(c.nav),
                        live_frame(plan.sensors.front()->job, c.nav_origin, "rig"), poses, {});
    const auto& stop = install_stop_signal();
    nav.start();
    std::fprintf(stderr, "%smirage rig: waiting for navigation on %s%s\n", describe(plan).c_str(),
                 c.nav.c_str(),
                 nav.udp_port() ? fmt::format(" (udp port {})", nav.udp_port()).c_str() : "");
    if (!wait_first_pose(poses, nav, c.nav, c.first_nav_timeout_s, stop, "rig")) return;
    const std::int64_t t0 = live_pulse0_ns(nav);
    const auto sender = make_sender(rt_priority);
    std::vector<std::unique_ptr<RigRun>> runs;
    LiveOptions lo;
    lo.status_line = false;
    lo.duration = plan.live_duration_ns;
    // One sensor clock: every output anchored with the same INS-to-host offset.
    const std::int64_t anchor = t0 + nav.offset_ns().value_or(0) + kLivePipelineDelay.count();
    for (auto& s : plan.sensors) {
        s->job.options.start = core::GpsTime(core::Nanos(t0));
        runs.push_back(open_run(*s, sender));
        lo.message_latency = runs.size() == 1;
        runs.back()->session =
            std::make_unique<LiveSession>(s->job, *runs.back()->out, nav, poses, lo);
        runs.back()->out->anchor(s->job.options.start, anchor);
    }
    std::fprintf(stderr, "mirage rig: pulse 0 at gps:%.3f\n", double(t0) / 1e9);
    run_all(runs, status, stop, [&stop](RigRun& r) {
        const Job& job = r.sensor->job;
        r.live = r.session->run(*r.wire.packetizer,
                                pulses_per_packet(job, r.sensor->packets_per_second), stop);
        r.wire.packetizer->finish();
    });
    nav.stop();
    const auto nc = nav.counters();
    std::printf(
        "mirage rig: navigation: %s%s%s; INS->packet latency (%s) p50 %.3f ms p99 %.3f ms\n",
        navpose::nav_counters_line(nc.decode, nc.track).c_str(), nc.detail.empty() ? "" : "; ",
        nc.detail.c_str(), runs.front()->sensor->entry.name.c_str(),
        double(runs.front()->live.latency.percentile(0.5).count()) / 1e6,
        double(runs.front()->live.latency.percentile(0.99).count()) / 1e6);
}

}  // namespace

void register_rig(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "rig", "Run a vehicle's lidars from a rig file: one scene, one trajectory, one clock");
    struct Opts {
        std::string file, duration;
        bool check = false, no_status = false;
        int rt_priority = 0;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("file", o->file, "Rig file (YAML; docs/rig.md)")->required();
    cmd->add_flag("--check", o->check,
                  "Validate the rig file and print the effective configuration; send nothing");
    cmd->add_option("--duration", o->duration, "Seconds to run (overrides the rig file's)");
    cmd->add_flag("--no-status", o->no_status, "No status line on stderr");
    cmd->add_option("--rt-priority", o->rt_priority,
                    "Send from a SCHED_FIFO thread at this priority (1-99; needs CAP_SYS_NICE)")
        ->check(CLI::Range(0, 99));
    cmd->callback([o] {
        const rig::RigConfig config = rig::load_rig(o->file);
        RigPlan plan = plan_rig(config, o->duration);
        if (o->check) {
            std::printf("%s", describe(plan).c_str());
            return;
        }
        if (plan.config.nav.empty())
            run_rig(plan, !o->no_status, o->rt_priority);
        else
            run_rig_live(plan, !o->no_status, o->rt_priority);
    });
}

}  // namespace mirage::hil
