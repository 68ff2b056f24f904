// SPDX-License-Identifier: Apache-2.0
#include "rig_run.hpp"

#include <fmt/format.h>
#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <thread>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navpose/nav_counters.hpp"
#include "mirage/navproto/protocol.hpp"
#include "mirage/output/packetizer_sink.hpp"
#include "mirage/udp/shared_sender.hpp"
#include "paced_sender.hpp"
#include "summary.hpp"

namespace mirage::hil {
namespace {

// From anchoring to the first send: every sensor's renderer starts at once on a few cores, so the
// rig waits longer than one `mirage emulate` (100 ms) before its first packet is due.
constexpr core::Nanos kRigStartLead{500'000'000};
// Live: packets leave this long after their firing time (`mirage live --pipeline-delay-us`).
constexpr core::Nanos kLivePipelineDelay{250'000};

// The renderer's points into the sensor's LAS file (before any fault), then on to `next`.
class LasTee final : public wire::Packetizer {
  public:
    LasTee(las::LasWriter& w, wire::Packetizer& next) : w_(w), next_(next) {}
    void add(std::span<const core::PointRecord> points) override {
        w_.write(points);
        next_.add(points);
    }
    void advance_to(std::uint64_t next_pulse) override { next_.advance_to(next_pulse); }
    void emit_side_packets_until(core::GpsTime t) override { next_.emit_side_packets_until(t); }
    void finish() override { next_.finish(); }

  private:
    las::LasWriter& w_;
    wire::Packetizer& next_;
};

// A packet on its way out: a stopped sensor withholds it, a drop burst takes it, else it goes
// to the live session (which times INS messages to it) or straight to the output.
void send(RigRun& r, const wire::PacketView& p) {
    const control::FaultSettings f = r.cell->load();
    r.newest_ns.store(p.time.time_since_epoch().count(), std::memory_order_relaxed);
    if (f.stop || (r.halt && r.halt->load(std::memory_order_relaxed))) {
        // Quiet from now: what was rendered ahead and queued goes too (docs/control.md §5).
        if (!r.quiet.exchange(true, std::memory_order_relaxed)) r.out->discard_queued();
        r.withheld.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    if (r.quiet.load(std::memory_order_relaxed)) r.quiet.store(false, std::memory_order_relaxed);
    if (r.dropper->drop(f)) {
        r.dropped.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    if (r.session)
        r.session->on_packet(p);
    else
        (*r.out)(p);
    r.packets.fetch_add(1, std::memory_order_relaxed);
}

// The sensor's encoder for its job's current start (a live rig builds it again when the INS's
// first pose moves the sensor clock from the host's to the INS's); before the first fix the
// position packets say there is none.
void rewire(RigRun& r, std::uint32_t index, bool gps_locked = true) {
    const RigSensor& s = *r.sensor;
    RigRun* raw = &r;
    r.faulty.reset();
    wire::WireContext ctx = wire_context(s.job);
    ctx.gps_locked = gps_locked;
    ctx.clock_step = r.clock ? &r.clock->step() : nullptr;
    r.wire = wire::make_wire(
        ctx, s.wire, [raw](const wire::PacketView& p) { send(*raw, p); }, s.entry.to);
    r.faulty = std::make_unique<control::FaultPacketizer>(*r.wire.packetizer, *r.cell,
                                                          s.job.options.seed, index);
    r.las_tee.reset();
    if (r.las) r.las_tee = std::make_unique<LasTee>(*r.las, *r.faulty);
    r.input = r.las_tee ? r.las_tee.get() : static_cast<wire::Packetizer*>(r.faulty.get());
}

std::unique_ptr<RigRun> open_run(RigSensor& s, std::uint32_t index,
                                 const std::shared_ptr<udp::SharedSender>& sender,
                                 const control::FaultSettings& defaults,
                                 const control::ControlModel* control,
                                 const std::atomic<bool>* halt, bool gps_locked,
                                 hostclock::ClockStepFollower* clock) {
    auto r = std::make_unique<RigRun>();
    r->sensor = &s;
    r->clock = clock;
    output::PacketOutputOptions po;
    po.realtime = true;
    po.status_line = false;
    po.shared_sender = sender;
    po.pcap_path = s.entry.pcap;
    po.clock_follower = clock;
    output::route_streams(po, s.ports, s.entry.to, s.entry.source_port);
    r->out = std::make_unique<output::PacketOutput>(po);
    r->own_cell.store(defaults);
    r->cell = control ? &control->faults(index) : &r->own_cell;
    if (control) r->halt = halt;
    r->dropper = std::make_unique<control::PacketDropper>(s.job.options.seed, index);
    if (!s.entry.las.empty())
        r->las = std::make_unique<las::LasWriter>(s.entry.las, s.job.scene->georef);
    rewire(*r, index, gps_locked);
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
// trajectory run, the stale windows of a live one; what its faults took.
std::string sensor_line(const RigRun& r, double wall_s) {
    const auto& t = r.totals;
    std::string s = fmt::format(
        "  {}: {} packets ({:.2f} MB), {} points; sent {}, failed sends {}, pcap {}; lateness p50 "
        "{:.0f} µs, p99 {:.0f} µs, worst {:.0f} µs, late {}",
        r.sensor->entry.name, t.packets, double(t.bytes) / 1e6, r.faulty->points(), t.sent,
        t.send_failed, t.pcap_packets, double(t.p50.count()) / 1e3, double(t.p99.count()) / 1e3,
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
    if (r.dropped.load() || r.withheld.load() || r.faulty->stale_points() || t.discarded)
        s += fmt::format(
            "; faults: dropped {}, withheld {}, returns removed {}; unsent at the stop {}",
            r.dropped.load(), r.withheld.load(), r.faulty->stale_points(), t.discarded);
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
    std::fflush(stdout);
}

// The process's CPU seconds less --keep-awake's spinner.
double rig_cpu_seconds(const RigRunOptions& o) {
    return hostclock::process_cpu_seconds() - (o.awake ? o.awake->cpu_seconds() : 0.0);
}

std::vector<std::unique_ptr<RigRun>> open_runs(RigPlan& plan, const RigRunOptions& o,
                                               const std::shared_ptr<udp::SharedSender>& sender,
                                               bool gps_locked = true) {
    const auto defaults = rig_fault_defaults(plan.config);
    std::vector<std::unique_ptr<RigRun>> runs;
    for (std::size_t i = 0; i < plan.sensors.size(); ++i)
        runs.push_back(open_run(*plan.sensors[i], static_cast<std::uint32_t>(i), sender,
                                defaults[i], o.control, o.stop, gps_locked, o.clock));
    return runs;
}

// Runs `body` for every sensor on its own thread, with the status line, then the summary.
// `before_first_pose`: the outputs stay open for the run that follows.
void run_all(std::vector<std::unique_ptr<RigRun>>& runs, const RigRunOptions& o,
             const std::function<void(RigRun&)>& body, bool before_first_pose = false) {
    const double cpu0 = rig_cpu_seconds(o);
    const auto w0 = std::chrono::steady_clock::now();
    std::vector<std::thread> threads;
    for (auto& r : runs) {
        r->running = true;
        threads.emplace_back([&r, &body, before_first_pose] {
            pthread_setname_np(pthread_self(), "mirage-rig");
            try {
                body(*r);
                if (r->halt && r->halt->load()) r->out->discard_queued();  // what slipped past
                if (!before_first_pose) {
                    r->totals = r->out->finish();
                    if (r->las) r->las->close();  // throws naming the file if writing failed
                }
            } catch (const std::exception& e) {
                r->error = e.what();
                r->failed = true;
                std::fprintf(stderr, "\nmirage rig: sensor '%s' failed: %s\n",
                             r->sensor->entry.name.c_str(), e.what());
            }
            r->running = false;
        });
    }
    std::atomic<bool> done{false};
    std::thread status_thread;
    if (o.status_line) status_thread = std::thread([&] { status_loop(runs, done); });
    for (auto& t : threads) t.join();
    done = true;
    if (status_thread.joinable()) status_thread.join();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    if (before_first_pose)
        std::printf(
            "mirage rig: before the first pose: %.3f s of packets without returns (%llu "
            "from the first sensor)\n",
            wall, static_cast<unsigned long long>(runs.front()->packets.load()));
    else
        print_summary(runs, wall, rig_cpu_seconds(o) - cpu0, o.stop->load());
    for (const auto& r : runs)
        if (!r->error.empty())
            throw IoError(fmt::format("rig: sensor '{}': {}", r->sensor->entry.name, r->error));
}

// Publishes the runs for the control plane while they run, and withdraws them however the run
// ends (the runs die with the caller's frame).
struct Published {
    RigView* view;
    Published(RigView* v, std::vector<std::unique_ptr<RigRun>>& runs, const navio::NavInput* nav,
              const navpose::PoseBuffer* poses)
        : view(v) {
        if (view) view->publish(&runs, nav, poses);
    }
    ~Published() {
        if (view) view->clear();
    }
    Published(const Published&) = delete;
    Published& operator=(const Published&) = delete;
};

// Every sensor streams without returns on the host's clock (pulse 0 at the host's GPS time)
// until the first full pose; `lo.duration` keeps what is left of the run. False when the run
// ended first (stopped, or its duration passed): the outputs are then finished.
bool stream_rig_before_first_pose(RigPlan& plan, const RigRunOptions& o,
                                  const std::shared_ptr<udp::SharedSender>& sender,
                                  navio::NavInput& nav, const navpose::PoseBuffer& poses,
                                  LiveOptions& lo, std::vector<std::unique_ptr<RigRun>>& runs) {
    std::fprintf(stderr,
                 "mirage rig: no full pose yet: streaming without returns on the host "
                 "clock until one arrives\n");
    const double cpu0 = rig_cpu_seconds(o);
    const std::int64_t off = host_gps_offset_ns();
    const std::int64_t h0 = host_gps_time_ahead(kHostPulse0Lead).time_since_epoch().count();
    for (auto& s : plan.sensors) s->job.options.start = core::GpsTime(core::Nanos(h0));
    runs = open_runs(plan, o, sender, false);
    LiveOptions l1 = before_first_pose(lo, off);
    for (auto& r : runs) {
        l1.faults = r->cell;
        r->session = std::make_unique<LiveSession>(r->sensor->job, *r->out, nav, poses, l1);
        r->out->anchor(r->sensor->job.options.start, h0 + off + kLivePipelineDelay.count());
    }
    const std::atomic<bool>& stop = *o.stop;
    Published pub(o.view, runs, &nav, &poses);  // withdrawn before the encoders are rebuilt
    run_all(
        runs, o,
        [&stop](RigRun& r) {
            r.session->run(
                *r.input,
                live_window_pulses(r.sensor->job, r.sensor->packets_per_second, kLivePipelineDelay),
                stop);
            r.wire.packetizer->finish();
        },
        true);
    const core::Nanos elapsed(hostclock::monotonic_ns() - off - h0);
    if (lo.duration.count() > 0) lo.duration = std::max(core::Nanos(1), lo.duration - elapsed);
    if (stop.load() || !poses.newest()) {  // stopped, or the duration passed first
        for (auto& r : runs) {
            r->totals = r->out->finish();
            if (r->las) r->las->close();
        }
        print_summary(runs, double(elapsed.count()) / 1e9, rig_cpu_seconds(o) - cpu0, stop.load());
        return false;
    }
    return true;
}

}  // namespace

std::vector<control::FaultSettings> rig_fault_defaults(const rig::RigConfig& config) {
    std::vector<control::FaultSettings> out;
    for (const auto& s : config.sensors) {
        const rig::Faults& f = s.faults ? *s.faults : config.faults;
        control::FaultSettings x;
        x.drop_rate = static_cast<std::uint16_t>(std::lround(f.drop_rate * 10000));
        x.drop_burst = static_cast<std::uint16_t>(f.drop_burst);
        x.range_bias_mm = static_cast<std::int16_t>(std::lround(f.range_bias_m * 1000));
        x.range_noise_mm = static_cast<std::uint16_t>(std::lround(f.range_noise_m * 1000));
        x.freeze_nav = f.freeze_nav;
        x.stale_nav = f.stale_nav;
        x.stop = f.stop;
        out.push_back(x);
    }
    return out;
}

void RigView::publish(std::vector<std::unique_ptr<RigRun>>* runs, const navio::NavInput* nav,
                      const navpose::PoseBuffer* poses) {
    std::lock_guard lk(m_);
    runs_ = runs;
    nav_ = nav;
    poses_ = poses;
    rate_at_ns_ = 0;
    applied_at_ = rate_ = 0;
}

bool RigView::sensor_failed() const {
    std::lock_guard lk(m_);
    if (!runs_) return false;
    return std::any_of(runs_->begin(), runs_->end(),
                       [](const auto& r) { return r->failed.load(); });
}

control::RigStatus RigView::status() const {
    std::lock_guard lk(m_);
    control::RigStatus s;
    if (!runs_) return s;
    for (const auto& r : *runs_) {
        control::SensorStatus x;
        // Stopped by its fault before off: a stopped sensor's thread may end at once, and the
        // register still says why it is silent (docs/control.md).
        const bool stopped = r->cell->load().stop;
        x.state = r->failed.load() ? control::SensorState::Failed
                  : stopped        ? control::SensorState::Stopped
                  : !r->running    ? control::SensorState::Off
                                   : control::SensorState::Streaming;
        x.packets = r->packets.load(std::memory_order_relaxed);
        x.points = r->faulty->points();
        x.dropped = r->dropped.load(std::memory_order_relaxed);
        x.stale_periods = r->session ? r->session->stale_periods() : r->faulty->stale_periods();
        if (const auto c = r->out->channel_counters()) {
            x.late = c->late;
            x.send_failed = c->failed;
        }
        s.sim_time_ns = std::max(s.sim_time_ns, r->newest_ns.load(std::memory_order_relaxed));
        s.sensors.push_back(x);
    }
    if (nav_) {
        const auto nc = nav_->counters();
        s.nav_rejected = nc.decode.rejected() + nc.track.rejected();
        const std::int64_t now = hostclock::monotonic_ns();
        if (now - rate_at_ns_ >= 1'000'000'000) {  // samples applied over the last second
            if (rate_at_ns_ != 0)
                rate_ = (nc.track.applied - applied_at_) * 1'000'000'000 /
                        std::uint64_t(now - rate_at_ns_);
            rate_at_ns_ = now;
            applied_at_ = nc.track.applied;
        }
        s.nav_rate = rate_;
        if (poses_ && s.sim_time_ns != 0)
            if (const auto newest = poses_->newest())
                s.pose_age_ms = (s.sim_time_ns - newest->time_since_epoch().count()) / 1'000'000;
    }
    return s;
}

// A trajectory: every output's first pulse at the same host instant (one sensor clock).
void run_rig(RigPlan& plan, const RigRunOptions& o) {
    // One deadline-ordered thread sends every sensor's packets: with a pacing thread per sensor
    // the senders of a 2-core machine would wake each other late (docs/rig.md §2).
    const auto sender = make_paced_sender(o.rt_priority, o.awake, "rig");
    // Started "now": the first pulse on the host's GPS time ahead of the schedule, so every
    // packet carries CLOCK_REALTIME's time (docs/time.md §1); else the file's time, replayed.
    std::optional<hostclock::ClockStepFollower> clock;
    RigRunOptions ro = o;
    if (plan.start_now) {
        const core::GpsTime start = host_gps_time_ahead(kRigStartLead);
        for (auto& s : plan.sensors) move_start(s->job, start);
        clock.emplace([] { return -host_gps_offset_ns(); });  // and its steps (docs/time.md §1)
        ro.clock = &*clock;
    }
    auto runs = open_runs(plan, ro, sender);
    const core::GpsTime t0 = plan.sensors.front()->job.options.start;
    const std::int64_t anchor = plan.start_now
                                    ? t0.time_since_epoch().count() + host_gps_offset_ns()
                                    : hostclock::monotonic_ns() + kRigStartLead.count();
    for (auto& r : runs) r->out->anchor(t0, anchor);
    std::fprintf(stderr, "%s", describe(plan).c_str());
    Published pub(o.view, runs, nullptr, nullptr);
    const std::atomic<bool>& stop = *o.stop;
    run_all(runs, o, [&stop](RigRun& r) {
        output::PacketizerSink sink(*r.input);
        r.stats = render::render(r.sensor->job.setup(), sink, {}, &stop);
    });
    print_clock_steps(stdout, ro.clock);
}

// A live source: one reader and pose buffer for all sensors; pulse 0 of every sensor at the same
// INS time, each sensor rendering one packet's pulses as soon as their firing times have passed
// (mirage live's loop), the first one also timing INS messages to packets.
void run_rig_live(RigPlan& plan, const RigRunOptions& o) {
    const rig::RigConfig& c = plan.config;
    navpose::PoseBufferConfig pc;
    pc.max_extrapolation = core::Nanos(static_cast<std::int64_t>(c.max_extrapolation_ms * 1e6));
    navpose::PoseBuffer poses(pc);
    navio::NavInput nav(navproto::parse_nav_uri(c.nav),
                        live_frame(plan.sensors.front()->job, c.nav_origin, "rig"), poses, {});
    const std::atomic<bool>& stop = *o.stop;
    nav.start();
    std::fprintf(stderr, "%smirage rig: waiting for navigation on %s%s\n", describe(plan).c_str(),
                 c.nav.c_str(),
                 nav.udp_port() ? fmt::format(" (udp port {})", nav.udp_port()).c_str() : "");
    const auto sender = make_paced_sender(o.rt_priority, o.awake, "rig");
    std::vector<std::unique_ptr<RigRun>> runs;
    LiveOptions lo;
    lo.status_line = false;
    lo.duration = plan.live_duration_ns;
    // Without first_nav_timeout the sensors stream without returns on the host's clock until the
    // first full pose (docs/rig.md §2); with it, nothing is sent until then.
    const bool give_up = c.first_nav_timeout_s > 0;
    bool have_pose = false;
    {
        Published waiting(o.view, runs, &nav, &poses);  // navigation counters while nothing runs
        have_pose =
            give_up
                ? wait_first_pose(poses, nav, c.nav, c.first_nav_timeout_s, stop, "rig").has_value()
                : await_first_pose(poses, stop, kFirstPoseSettleS);
    }
    if (give_up && !have_pose) return;
    if (!give_up && !have_pose && !stop.load() &&
        !stream_rig_before_first_pose(plan, o, sender, nav, poses, lo, runs))
        return;
    const std::int64_t t0 = live_pulse0_ns(nav);
    // One sensor clock: every output anchored with the same INS-to-host offset.
    const std::int64_t anchor = t0 + nav.offset_ns().value_or(0) + kLivePipelineDelay.count();
    for (auto& s : plan.sensors) s->job.options.start = core::GpsTime(core::Nanos(t0));
    if (runs.empty())
        runs = open_runs(plan, o, sender);
    else
        for (std::size_t i = 0; i < runs.size(); ++i) rewire(*runs[i], std::uint32_t(i));
    for (auto& r : runs) {
        lo.message_latency = &r == &runs.front();
        lo.faults = r->cell;
        r->session = std::make_unique<LiveSession>(r->sensor->job, *r->out, nav, poses, lo);
        r->out->anchor(r->sensor->job.options.start, anchor);
    }
    std::fprintf(stderr, "mirage rig: pulse 0 at gps:%.3f\n", double(t0) / 1e9);
    Published pub(o.view, runs, &nav, &poses);
    run_all(runs, o, [&stop](RigRun& r) {
        const Job& job = r.sensor->job;
        r.live = r.session->run(
            *r.input, live_window_pulses(job, r.sensor->packets_per_second, kLivePipelineDelay),
            stop);
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

}  // namespace mirage::hil
