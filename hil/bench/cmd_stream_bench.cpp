// SPDX-License-Identifier: Apache-2.0
// `mirage stream-bench` (issue 3, item 9): encoder throughput per model and mode; three sensors
// streaming at once in real time over loopback (CPU used, packet rates against the device's,
// lateness of every packet from kernel receive timestamps against its schedule); the bare pacing
// probe with and without SCHED_FIFO. Writes streams.md and streams.json.
#include <fmt/format.h>
#include <pthread.h>
#include <sys/utsname.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_report.hpp"
#include "commands.hpp"
#include "job.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/output/packetizer_sink.hpp"
#include "mirage/rig/rig_config.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/pacing_probe.hpp"
#include "mirage/udp/shared_sender.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "mirage/wire/setup.hpp"
#include "spin_gaps.hpp"
#include "stream_bench.hpp"
#include "stream_report.hpp"
#include "text_file.hpp"

namespace mirage::hil {
namespace {

struct Case {
    const char* label;
    const char* sensor;
    const char* mode;     // Velodyne return mode
    const char* profile;  // Ouster profile
};

constexpr const char* kRng19 = "RNG19_RFL8_SIG16_NIR16";
constexpr Case kEncoderCases[] = {
    {"VLP-16 strongest", "vlp16", "strongest", "LEGACY"},
    {"VLP-16 dual", "vlp16", "dual", "LEGACY"},
    {"VLP-32C strongest", "vlp32c", "strongest", "LEGACY"},
    {"HDL-32E strongest", "hdl32e", "strongest", "LEGACY"},
    {"HDL-64E S3 dual", "hdl64e-s3", "dual", "LEGACY"},
    {"OS1-64 1024x10 LEGACY", "os1-64-1024x10", "strongest", "LEGACY"},
    {"OS1-128 2048x10 RNG19", "os1-128-2048x10", "strongest", kRng19},
    {"OS1-128 2048x10 RNG15", "os1-128-2048x10", "strongest", "RNG15_RFL8_NIR8"},
};
constexpr Case kStreamCases[] = {
    {"VLP-16 strongest", "vlp16", "strongest", "LEGACY"},
    {"HDL-64E S3 dual", "hdl64e-s3", "dual", "LEGACY"},
    {"OS1-128 2048x10 RNG19", "os1-128-2048x10", "strongest", kRng19},
};

// One stream of the real-time run: its label, job inputs (sensor, trajectory, mount) and wire
// settings; the three benchmark cases or a rig file's sensors.
struct StreamSpec {
    std::string label;
    JobInputs in;
    wire::WireOptions wire;
    double rpm = 0;
};

wire::WireOptions wire_options(const Case& c) {
    wire::WireOptions w;
    w.return_mode = c.mode;
    w.profile = c.profile;
    return w;
}

Machine machine_now() {
    Machine m;
    m.cpu = cpu_model();
    m.cores = std::thread::hardware_concurrency();
    std::ifstream la("/proc/loadavg");
    std::string a, b, c;
    la >> a >> b >> c;
    m.load = a + " " + b + " " + c;
    utsname u{};
    if (uname(&u) == 0) m.kernel = std::string(u.sysname) + " " + u.release;
    return m;
}

// ---- 1. Encoder throughput ------------------------------------------------------------------

struct EncodeCount {
    std::uint64_t data = 0, aux = 0, bytes = 0;
    void operator()(const wire::PacketView& p) {
        if (p.stream != wire::Stream::Data) {
            ++aux;
            return;
        }
        ++data;
        bytes += p.bytes.size();
    }
};

// Synthetic returns for every pulse of `span` (two per pulse in dual mode) into the packetizer;
// only the packetizer calls are timed. Returns the seconds spent in them.
double time_encoder(wire::Packetizer& packetizer, const Job& job, bool dual, core::Nanos span,
                    std::uint64_t& pulses) {
    const std::uint64_t total = job.sensor.scan->pulse_count(span);
    const std::size_t chunk = render::chunk_pulses(job.sensor, 8192);
    std::vector<sensor::PulseSpec> specs(chunk);
    std::vector<core::PointRecord> pts;
    pts.reserve(chunk * 2);
    double encode_s = 0;
    for (std::uint64_t first = 0; first < total; first += chunk) {
        const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(chunk, total - first));
        job.sensor.scan->pulses(first, n, specs.data());
        pts.clear();
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint64_t k = first + i;
            core::PointRecord r;
            r.t = job.options.start + core::Nanos{specs[i].t_ns};
            r.pulse = k;
            r.channel = specs[i].channel;
            r.azimuth_deg = specs[i].azimuth_deg;
            r.range_m = 3.0f + static_cast<float>((k * 7919) % 60000) * 1e-3f;  // 3–63 m
            r.n_laser = 40.0 + static_cast<double>(k % 400);
            r.intensity = static_cast<std::uint16_t>((k * 2654435761u) >> 16);
            if (dual) {
                r.number_of_returns = 2;
                pts.push_back(r);
                r.return_number = 2;
                r.range_m += 4.0f;
                r.n_laser *= 0.5;
            }
            pts.push_back(r);
        }
        const auto t0 = std::chrono::steady_clock::now();
        packetizer.add(pts);
        packetizer.advance_to(first + n);
        encode_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const auto t0 = std::chrono::steady_clock::now();
    packetizer.finish();
    encode_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    pulses = total;
    return encode_s;
}

// The encoder alone (Velodyne position packets from a fixed fix, Ouster IMU from the static
// trajectory), then the same through wire::make_wire as `mirage emulate` builds it.
EncoderRow bench_encoder(const Case& c, const std::shared_ptr<const scene::Scene>& scene,
                         core::Nanos span) {
    JobInputs in;
    in.sensor = c.sensor;
    in.trajectory = "static:0,0,2";
    Job job = load_job_with_scene(in, scene, 0, false);
    const wire::WireOptions wo = wire_options(c);
    wire::prepare_sensor(job.sensor, wo, 0);
    const bool dual = std::string(c.mode) == "dual";
    EncoderRow row;
    row.label = c.label;
    EncodeCount pure;
    std::unique_ptr<wire::Packetizer> p;
    if (const auto model = velodyne::model_from_name(job.sensor.wire.model)) {
        p = std::make_unique<velodyne::Packetizer>(
            velodyne::descriptor(*model), velodyne::parse_return_mode(wo.return_mode), job.sensor,
            job.options.start, [&pure](const wire::PacketView& v) { pure(v); });
    } else {
        p = wire::make_wire(
                wire_context(job), wo, [&pure](const wire::PacketView& v) { pure(v); }, "")
                .packetizer;
    }
    row.seconds = time_encoder(*p, job, dual, span, row.pulses);
    row.packets = pure.data;
    row.aux_packets = pure.aux;
    row.bytes = pure.bytes;
    row.packets_per_s = row.seconds > 0 ? static_cast<double>(pure.data) / row.seconds : 0;

    EncodeCount full;
    wire::WireSetup w = wire::make_wire(
        wire_context(job), wo, [&full](const wire::PacketView& v) { full(v); }, "");
    row.device_packets_per_s = w.packets_per_second;
    std::uint64_t pulses = 0;
    const double s = time_encoder(*w.packetizer, job, dual, span, pulses);
    row.emulate_packets_per_s = s > 0 ? static_cast<double>(full.data) / s : 0;
    return row;
}

// ---- 2. Three streams at once ---------------------------------------------------------------

// One emulated sensor: its pipeline, output and loopback receiver, and what each side measured.
struct StreamRun {
    std::string label;
    Job job;
    wire::WireSetup wire;
    std::unique_ptr<udp::UdpReceiver> rx;
    std::unique_ptr<output::PacketOutput> out;
    ScheduleRing ring;
    // Render writer thread.
    bool anchored = false;
    core::GpsTime t0{};
    std::int64_t anchor_ns = 0;
    std::vector<std::int64_t> handed_late;  // arrival at the output − deadline (< 0: ahead)
    std::vector<std::int64_t> late_at;      // schedule time (from the first packet) of those > 1 ms
    std::uint64_t data_handed = 0, aux_handed = 0, ring_full = 0;
    render::RenderStats stats;
    output::PacketOutputTotals totals;
    std::string error;
    // Receiver thread.
    std::vector<std::int64_t> wire_late;  // kernel receive time − deadline
    std::uint64_t rx_data = 0, rx_aux = 0, unmatched = 0, lost = 0, no_timestamp = 0;
    std::int64_t first_rx_ns = 0, last_rx_ns = 0;  // kernel times of first / last data packet
};

constexpr std::int64_t kLateHandOver_ns = 1'000'000;  // behind schedule: > 1 ms late

// The writer-thread side: record the packet's schedule, then hand it to the paced output. The
// first packet anchors both this schedule and the output's Pacer (first packet = now + emulate's
// start lead).
void hand_over(StreamRun& r, const wire::PacketView& p) {
    const std::uint64_t key = packet_key(p.bytes);
    const std::int64_t now = hostclock::monotonic_ns();
    if (!r.anchored) {
        r.anchored = true;
        r.t0 = p.time;
        r.anchor_ns = now + output::kEmulateStartLead.count();  // as emulate: a lead before sending
        r.out->anchor(r.t0, r.anchor_ns);  // the Pacer's schedule is exactly the one measured
    }
    const std::int64_t deadline = r.anchor_ns + (p.time - r.t0).count();
    const bool data = p.stream == wire::Stream::Data;
    r.handed_late.push_back(now - deadline);
    if (now - deadline > kLateHandOver_ns) r.late_at.push_back(deadline - r.anchor_ns);
    if (!r.ring.push({key, deadline, data})) ++r.ring_full;
    ++(data ? r.data_handed : r.aux_handed);
    (*r.out)(p);
}

// Reads what has arrived, then sleeps 1 ms: the kernel stamps each datagram as it is sent, so
// reading later changes no figure, while a receiver blocked in poll() would be woken by every
// send, inside the sender's system call, and lengthen it (docs/benchmarks.md §2). A remote
// client costs the emulator no wake-ups either.
void receive_loop(StreamRun& r, std::int64_t rt_minus_mono, const std::atomic<bool>& done) {
    udp::ReceivedDatagram d;
    for (;;) {
        if (!r.rx->receive(d, core::Nanos{0})) {
            if (done.load(std::memory_order_acquire)) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            continue;
        }
        ScheduledPacket s;
        if (!r.ring.match(packet_key(d.payload), s, r.lost)) {
            ++r.unmatched;
            continue;
        }
        if (d.kernel_time_ns == 0) {
            ++r.no_timestamp;
            continue;
        }
        r.wire_late.push_back(d.kernel_time_ns - rt_minus_mono - s.deadline_ns);
        if (!s.data) {
            ++r.rx_aux;
            continue;
        }
        if (r.rx_data++ == 0) r.first_rx_ns = d.kernel_time_ns;
        r.last_rx_ns = d.kernel_time_ns;
    }
}

StreamRow summarize_stream(const StreamRun& r, double seconds) {
    StreamRow s;
    s.label = r.label;
    s.device_packets_per_s = r.wire.packets_per_second;
    s.expected_data = seconds * r.wire.packets_per_second;
    s.data_sent = r.data_handed;
    s.aux_sent = r.aux_handed;
    s.data_received = r.rx_data;
    s.aux_received = r.rx_aux;
    s.failed_sends = r.totals.send_failed;
    s.lost = r.lost;
    s.unmatched = r.unmatched;
    s.ring_full = r.ring_full;
    if (r.rx_data > 1 && r.last_rx_ns > r.first_rx_ns)
        s.rx_packets_per_s = static_cast<double>(r.rx_data - 1) * 1e9 /
                             static_cast<double>(r.last_rx_ns - r.first_rx_ns);
    s.rate_error = s.device_packets_per_s > 0 ? s.rx_packets_per_s / s.device_packets_per_s - 1 : 0;
    s.pacer_late = r.totals.late;
    s.pacer_p99_us = us(r.totals.p99.count());
    s.pacer_worst_us = us(r.totals.worst_late.count());
    s.send_p50_us = us(r.totals.send_p50.count());
    s.send_p99_us = us(r.totals.send_p99.count());
    s.handed_late_1ms = r.late_at.size();
    if (!r.handed_late.empty()) {
        s.handed_worst_ms =
            static_cast<double>(*std::max_element(r.handed_late.begin(), r.handed_late.end())) /
            1e6;
        s.handed_ahead_p50_ms = -static_cast<double>(summarize(r.handed_late).p50) / 1e6;
    }
    if (!r.late_at.empty()) {
        s.late_first_s = static_cast<double>(r.late_at.front()) / 1e9;
        s.late_last_s = static_cast<double>(r.late_at.back()) / 1e9;
    }
    s.wire = summarize(r.wire_late);
    if (!r.wire_late.empty())
        s.wire_late_50us_share = double(std::count_if(r.wire_late.begin(), r.wire_late.end(),
                                                      [](std::int64_t x) { return x > 50'000; })) /
                                 double(r.wire_late.size());
    s.pulses = r.stats.pulses;
    s.points = r.stats.points;
    s.cpu_render_s = r.stats.cpu_rays_s + r.stats.cpu_trace_s + r.stats.cpu_shade_s;
    s.cpu_output_s = r.stats.cpu_output_s;
    s.error = r.error;
    // Real time: the device's packet rate within 0.5 %, every packet delivered, and the pipeline
    // never behind its schedule.
    s.real_time = r.error.empty() && s.data_received > 0 && std::abs(s.rate_error) <= 0.005 &&
                  s.data_received == s.data_sent && s.failed_sends == 0 && s.handed_late_1ms == 0;
    return s;
}

StreamsResult run_streams(const std::shared_ptr<const scene::Scene>& scene, double seconds_scene,
                          const std::vector<StreamSpec>& specs, const std::string& seconds,
                          int render_threads, std::size_t chunk_pulses, int fifo_priority,
                          bool shared, int spin_margin_us, const hostclock::KeepAwake* awake) {
    StreamsResult res;
    res.fifo_priority = fifo_priority;
    res.shared = shared;
    std::shared_ptr<udp::SharedSender> sender;
    if (shared) {
        // One deadline-ordered thread sends all three streams (FIFO when allowed).
        udp::SharedSenderConfig sc;
        sc.fifo_priority = fifo_priority;  // the writer threads stay SCHED_OTHER
        sc.spin_margin = core::Nanos{std::int64_t{spin_margin_us} * 1'000};
        sc.cpu = hostclock::sending_cpu_of(awake);
        sender = std::make_shared<udp::SharedSender>(sc);
        res.spin_margin_us = spin_margin_us;
        res.horizon_ms = static_cast<double>(sc.horizon.count()) / 1e6;
        res.fifo = sender->fifo();
        res.fifo_error = sender->fifo_error();
    }
    res.render_threads = render_threads;
    res.chunk_pulses = chunk_pulses;
    res.trajectory = specs.empty() ? std::string() : specs.front().in.trajectory;
    res.render_lead_ms =
        std::chrono::duration<double, std::milli>(output::kEmulateRenderLead).count();
    const double secs = static_cast<double>(parse_seconds(seconds, "--seconds").count()) / 1e9;
    std::vector<std::unique_ptr<StreamRun>> runs;
    for (const StreamSpec& spec : specs) {
        auto r = std::make_unique<StreamRun>();
        r->label = spec.label;
        JobInputs in = spec.in;
        in.duration = seconds;
        in.threads = render_threads;
        r->job = load_job_with_scene(in, scene, seconds_scene, runs.empty());
        if (!runs.empty()) r->job.renderer = runs.front()->job.renderer;  // one BVH for all
        r->job.options.chunk_pulses = chunk_pulses;
        const wire::WireOptions& wo = spec.wire;
        wire::prepare_sensor(r->job.sensor, wo, spec.rpm);
        set_render_lead(r->job, output::kEmulateRenderLead);  // as emulate
        r->rx = std::make_unique<udp::UdpReceiver>();
        const bool ouster = r->job.sensor.wire.family == sensor::WireFamily::Ouster;
        output::PacketOutputOptions po;
        po.realtime = true;
        po.status_line = false;
        po.fifo_priority = fifo_priority;  // as `mirage emulate --rt-priority`
        po.shared_sender = sender;         // null: per-stream pacing in the writer threads
        udp::SenderConfig sc;
        sc.host = "127.0.0.1";
        // Data and position / IMU to the same receiver; the schedule ring tells them apart.
        sc.ports = udp::StreamPorts{r->rx->port(), ouster ? std::uint16_t{0} : r->rx->port(),
                                    ouster ? r->rx->port() : std::uint16_t{0}};
        po.udp = sc;
        r->out = std::make_unique<output::PacketOutput>(po);
        StreamRun* raw = r.get();
        r->wire = wire::make_wire(
            wire_context(r->job), wo, [raw](const wire::PacketView& p) { hand_over(*raw, p); },
            "127.0.0.1");
        // Reserve the per-packet series so the hot path never reallocates.
        const auto expect = static_cast<std::size_t>(secs * (r->wire.packets_per_second + 200.0));
        r->handed_late.reserve(expect + 4096);
        r->late_at.reserve(4096);  // a few late ones should not allocate either
        r->wire_late.reserve(expect + 4096);
        runs.push_back(std::move(r));
    }
    const std::int64_t rt_minus_mono = hostclock::realtime_minus_monotonic();

    std::atomic<bool> done{false};
    std::vector<std::thread> receivers, senders;
    for (auto& r : runs)
        receivers.emplace_back([&r, rt_minus_mono, &done] {
            pthread_setname_np(pthread_self(), "mirage-rx");
            receive_loop(*r, rt_minus_mono, done);
        });
    // The CPU the streams use: the process's, less what --keep-awake's spinners took.
    const auto cpu_now = [awake] {
        return hostclock::process_cpu_seconds() - (awake ? awake->cpu_seconds() : 0.0);
    };
    const double cpu0 = cpu_now();
    const auto w0 = std::chrono::steady_clock::now();
    for (auto& r : runs)
        senders.emplace_back([&r] {
            pthread_setname_np(pthread_self(), "mirage-writer");
            try {
                output::PacketizerSink sink(*r->wire.packetizer);
                r->stats = render::render(r->job.setup(), sink);
                r->totals = r->out->finish();
            } catch (const std::exception& e) {
                r->error = e.what();
            }
        });
    for (auto& t : senders) t.join();
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    res.cpu_s = cpu_now() - cpu0;
    done.store(true, std::memory_order_release);
    for (auto& t : receivers) t.join();
    for (const auto& r : runs) res.rows.push_back(summarize_stream(*r, secs));
    if (sender) {
        res.sender_cpu_s = sender->cpu_seconds();
        res.sender_wakeups = sender->wakeups();
        res.horizon_waits = sender->horizon_waits();
        res.full_waits = sender->full_waits();
        const udp::LatenessHistogram w = sender->wake_lateness();
        res.wake_late_p50_us = us(w.percentile(0.50).count());
        res.wake_late_p99_us = us(w.percentile(0.99).count());
    } else {
        res.fifo = !runs.empty() && std::all_of(runs.begin(), runs.end(),
                                                [](const auto& r) { return r->totals.fifo; });
        for (const auto& r : runs)
            if (!r->totals.fifo_error.empty()) res.fifo_error = r->totals.fifo_error;
    }
    return res;
}

// ---- 3. Pacing probe ------------------------------------------------------------------------

ProbeRow run_probe(double seconds, int fifo_priority) {
    ProbeRow row;
    row.label = fifo_priority > 0 ? fmt::format("10 kHz, SCHED_FIFO {}", fifo_priority)
                                  : std::string("10 kHz, SCHED_OTHER");
    if (fifo_priority > 0) {
        // Ask on a scratch thread so a refusal is reported instead of printed by the probe.
        bool ok = false;
        std::string why;
        std::thread([&] { ok = udp::set_realtime_priority(fifo_priority, why); }).join();
        if (!ok) {
            row.note = "SCHED_FIFO not permitted: " + why;
            return row;
        }
    }
    udp::PacingProbeConfig pc;
    pc.rate_hz = 10'000;
    pc.packets = static_cast<std::uint64_t>(seconds * pc.rate_hz);
    pc.fifo_priority = fifo_priority;
    row.report = udp::run_pacing_probe(pc);
    row.ran = true;
    return row;
}

// The floor: spin on the clock for `seconds` now (on `cpu` when >= 0); the gaps are added to
// `gaps`.
void spin_floor(double seconds, std::vector<Gap>& gaps, std::int64_t& span, int cpu) {
    std::thread([&] {
        pthread_setname_np(pthread_self(), "mirage-floor");
        std::string why;
        if (cpu >= 0 && !hostclock::pin_current_thread(cpu, why))
            std::fprintf(stderr, "stream-bench: floor not pinned to %s\n", why.c_str());
        const std::int64_t start = hostclock::monotonic_ns() + 1'000'000;
        const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
        const std::vector<Gap> g = spin_gaps(start, end);
        gaps.insert(gaps.end(), g.begin(), g.end());
        span += end - start;
    }).join();
}

Floor summarize_floor(const std::vector<Gap>& gaps, std::int64_t span) {
    Floor f;
    f.seconds = double(span) / 1e9;
    f.share_50us = delayed_share(gaps, span, 50'000);
    f.p99_us = double(delay_exceeded_by(gaps, span, 0.01)) / 1e3;
    for (const Gap& g : gaps) f.worst_us = std::max(f.worst_us, double(g.end - g.begin) / 1e3);
    return f;
}

// A rig file's sensor as a stream: its sensor, mount and wire settings on the rig's trajectory
// (its destinations are replaced by the benchmark's loopback receivers).
StreamSpec rig_stream(const rig::SensorEntry& e, const rig::RigConfig& c) {
    StreamSpec spec;
    spec.label = e.name;
    spec.in.sensor = e.sensor;
    spec.in.trajectory = c.trajectory;
    spec.in.start = c.start == "now" ? std::string() : c.start;
    spec.in.lever_arm.assign(e.lever_arm.begin(), e.lever_arm.end());
    spec.in.boresight.assign(e.boresight.begin(), e.boresight.end());
    spec.wire.return_mode = e.return_mode;
    spec.wire.profile = e.profile;
    spec.rpm = e.rpm;
    return spec;
}

}  // namespace

void register_stream_bench(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "stream-bench",
        "Streaming benchmark: encoder throughput, three sensors streaming at once in real time "
        "over loopback (CPU, packet rates, kernel-timestamp pacing error), pacing probe");
    struct Opts {
        std::string seconds = "60";
        std::string out_dir = "bench-results";
        std::string trajectory = "demo-car";
        int render_threads = 2;
        std::size_t chunk_pulses = 16384;
        int fifo_priority = 10;
        std::string sender = "shared";
        int spin_margin_us = 50;
        std::string probe_seconds;  // empty: as --seconds
        std::string rig;            // a rig file's sensors instead of the three cases
        double floor_seconds = 10;  // the spinning thread's, around the streams
        bool quick = false, keep_awake = false;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--seconds", o->seconds,
                    "Seconds of the real-time streams and of each pacing probe run")
        ->capture_default_str();
    cmd->add_option("--probe-seconds", o->probe_seconds,
                    "Seconds of each pacing probe run if not --seconds (0: no probe)");
    cmd->add_option("--out-dir", o->out_dir, "Where streams.md and streams.json go")
        ->capture_default_str();
    cmd->add_option("--trajectory", o->trajectory,
                    "demo-car or static:x,y,z[,roll,pitch,yaw] on the demo town")
        ->capture_default_str();
    cmd->add_option("--render-threads", o->render_threads,
                    "Render worker threads per stream (each stream also has its writer thread)")
        ->capture_default_str();
    cmd->add_option("--chunk-pulses", o->chunk_pulses,
                    "Pulses per render work unit (the pipeline's lead over the schedule)")
        ->capture_default_str();
    cmd->add_option("--fifo-priority", o->fifo_priority,
                    "SCHED_FIFO priority of the streams' sending threads (as emulate "
                    "--rt-priority) and of the second pacing probe run (0: neither)")
        ->check(CLI::Range(0, 99))
        ->capture_default_str();
    cmd->add_option("--sender", o->sender,
                    "shared: one deadline-ordered thread sends all streams; per-stream: each "
                    "stream's writer thread paces and sends its own (the old path)")
        ->check(CLI::IsMember({"shared", "per-stream"}))
        ->capture_default_str();
    cmd->add_option("--spin-margin-us", o->spin_margin_us,
                    "Shared sender: sleep until this long before a deadline, then spin (less: "
                    "less CPU, more exposure to late timer wake-ups)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    cmd->add_option("--rig", o->rig,
                    "Stream a rig file's sensors (scene, trajectory, mounts, wire settings; "
                    "docs/rig.md) instead of the three cases, each to its own loopback receiver; "
                    "no encoder section")
        ->check(CLI::ExistingFile);
    cmd->add_option("--floor-seconds", o->floor_seconds,
                    "The machine's floor: a thread spinning on the clock, half this long just "
                    "before the streams and half just after (0: none; --quick: 1; with "
                    "--keep-awake a quarter each with and without the spinners)")
        ->check(CLI::Range(0.0, 600.0))
        ->capture_default_str();
    cmd->add_flag("--keep-awake", o->keep_awake,
                  "Pin the shared sender to one CPU kept out of idle by a SCHED_IDLE spinner "
                  "during the floor and the streams (as emulate/rig --keep-awake; needs --sender "
                  "shared; docs/time.md §5)");
    cmd->add_flag("--quick", o->quick, "Short run for CI: 3 s streams, short encoder runs");
    cmd->callback([o] {
        Report rep;
        rep.machine = machine_now();  // load average before we add our own
        rep.quick = o->quick;
        rep.seconds = o->quick ? "3" : o->seconds;
        if (o->render_threads < 1)
            throw ConfigError("stream-bench: --render-threads: expected at least 1");
        if (o->keep_awake && o->sender != "shared")
            throw ConfigError("stream-bench: --keep-awake needs --sender shared");
        const double secs =
            static_cast<double>(parse_seconds(rep.seconds, "--seconds").count()) / 1e9;
        std::error_code ec;
        std::filesystem::create_directories(o->out_dir, ec);
        if (ec)
            throw IoError(
                fmt::format("stream-bench: cannot create '{}': {}", o->out_dir, ec.message()));
        std::printf("mirage stream-bench: %s, %u cores, load %s\n", rep.machine.cpu.c_str(),
                    rep.machine.cores, rep.machine.load.c_str());
        std::fflush(stdout);
        std::vector<StreamSpec> specs;
        std::optional<rig::RigConfig> rig_config;
        if (!o->rig.empty()) rig_config = rig::load_rig(o->rig);
        if (rig_config && !rig_config->nav.empty())
            throw ConfigError("stream-bench: rig '" + o->rig +
                              "': navigation.nav is a live source; the benchmark needs a "
                              "trajectory");
        auto scene = load_scene_timed(rig_config ? rig_config->scene : "demo", rep.scene_seconds);
        if (rig_config) {
            for (const rig::SensorEntry& e : rig_config->sensors)
                specs.push_back(rig_stream(e, *rig_config));
        } else {
            for (const Case& c : kStreamCases) {
                StreamSpec spec{c.label, {}, wire_options(c), 0};
                spec.in.sensor = c.sensor;
                spec.in.trajectory = o->trajectory;
                specs.push_back(spec);
            }
        }

        // 1. Encoder throughput (not with --rig: the rig's streams are the question).
        const core::Nanos span = o->quick ? core::Nanos{std::chrono::milliseconds(300)}
                                          : core::Nanos{std::chrono::seconds(3)};
        if (!rig_config)
            for (const Case& c : kEncoderCases)
                rep.encoder.push_back(bench_encoder(c, scene, span));

        // 2. The streams at once.
        std::printf("streaming %s s: %zu sensors at once%s...\n", rep.seconds.c_str(), specs.size(),
                    rig_config ? (" (rig " + o->rig + ")").c_str() : "");
        std::fflush(stdout);
        // The floor in the same run: half just before the streams, half just after. With
        // --keep-awake, as the streams see the machine (spinners on) and as it is (off), a
        // quarter each, off on the outside: the targets take the stricter.
        const double floor_s = o->quick ? 1.0 : o->floor_seconds;
        const double part_s = o->keep_awake ? floor_s / 4 : floor_s / 2;
        // Like for like: the floor spins where the sender runs (the CPU kept awake).
        const int cpu = o->keep_awake ? hostclock::sending_cpu() : -1;
        std::vector<Gap> floor_gaps, plain_gaps;
        std::int64_t floor_span = 0, plain_span = 0;
        if (floor_s > 0 && o->keep_awake) spin_floor(part_s, plain_gaps, plain_span, cpu);
        std::optional<hostclock::KeepAwake> awake;
        if (o->keep_awake) awake.emplace(std::vector<int>{cpu});
        if (floor_s > 0) spin_floor(part_s, floor_gaps, floor_span, cpu);
        rep.streams = run_streams(scene, rep.scene_seconds, specs, rep.seconds, o->render_threads,
                                  o->chunk_pulses, o->fifo_priority, o->sender == "shared",
                                  o->spin_margin_us, awake ? &*awake : nullptr);
        if (floor_s > 0) {
            spin_floor(part_s, floor_gaps, floor_span, cpu);
            rep.floor = summarize_floor(floor_gaps, floor_span);
        }
        if (awake) {
            rep.streams.keep_awake_threads = awake->threads();
            rep.streams.keep_awake_warning = awake->warning();
            if (rep.streams.keep_awake_warning.empty() && !rep.streams.fifo_error.empty())
                rep.streams.keep_awake_warning = "sender " + rep.streams.fifo_error;
            awake.reset();  // the pacing probe measures the machine as it is
            if (floor_s > 0) {
                spin_floor(part_s, plain_gaps, plain_span, cpu);
                rep.floor_plain = summarize_floor(plain_gaps, plain_span);
            }
        }
        rep.streams.rig = o->rig;

        // 3. Pacing probe, by default as long as the streams (--quick: 1 s each, to keep the
        // CI test short).
        const double probe_s =
            o->quick ? 1.0
            : o->probe_seconds.empty()
                ? secs
                : static_cast<double>(parse_seconds(o->probe_seconds, "--probe-seconds").count()) /
                      1e9;
        if (probe_s > 0) {
            std::printf("pacing probe at 10 kHz...\n");
            std::fflush(stdout);
            rep.probes.push_back(run_probe(probe_s, 0));
            if (o->fifo_priority > 0) rep.probes.push_back(run_probe(probe_s, o->fifo_priority));
        }

        // 4. Reports.
        const std::string md = stream_markdown(rep);
        const std::filesystem::path dir(o->out_dir);
        write_text_file((dir / "streams.md").string(), md, "stream-bench");
        write_text_file((dir / "streams.json").string(), stream_json(rep), "stream-bench");
        std::printf("\n%s\nwrote %s and %s\n", md.c_str(), (dir / "streams.md").string().c_str(),
                    (dir / "streams.json").string().c_str());
        for (const auto& t : rep.streams.rows)
            if (!t.error.empty()) throw CLI::RuntimeError(1);
    });
}

}  // namespace mirage::hil
