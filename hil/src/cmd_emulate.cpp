// SPDX-License-Identifier: Apache-2.0
// `mirage emulate`: a fake Velodyne / Ouster on the network — the core's returns encoded as the
// vendor's UDP packets, paced on the sensor clock, optionally captured to a pcap.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include "commands.hpp"
#include "job.hpp"
#include "keep_awake_option.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/output/packetizer_sink.hpp"
#include "mirage/wire/setup.hpp"
#include "paced_sender.hpp"
#include "stop_signal.hpp"
#include "summary.hpp"
#include "text_file.hpp"

namespace mirage::hil {
namespace {

std::string default_side_path(const std::string& pcap, const std::string& ext) {
    std::filesystem::path p(pcap);
    p.replace_extension(ext);
    return p.string();
}

}  // namespace

void register_emulate(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "emulate",
        "Stream a fake Velodyne or Ouster sensor as UDP packets (and/or a pcap) from a scene");
    struct Opts {
        JobInputs job;
        std::string pose;
        std::string to;
        std::uint16_t data_port = 0, position_port = 8308, imu_port = 7503, source_port = 0;
        wire::WireOptions wire;
        double rpm = 0;
        std::string pcap;
        std::string calibration_out;
        bool realtime = false, afap = false, no_status = false, keep_awake = false;
        int rt_priority = 0;
    };
    auto o = std::make_shared<Opts>();
    add_job_options(*cmd, o->job);
    cmd->add_option("--pose", o->pose,
                    "Static sensor pose x,y,z[,roll,pitch,yaw] (local m, deg); instead of "
                    "--trajectory");
    cmd->add_option("--to", o->to,
                    "Destination IPv4 host: unicast, broadcast (255.255.255.255 or a subnet's) "
                    "or multicast (224.0.0.0/4); without it nothing is sent");
    cmd->add_option("--data-port", o->data_port,
                    "Destination port of lidar data (default 2368 Velodyne, 7502 Ouster)");
    cmd->add_option("--position-port", o->position_port, "Velodyne position packets (0: off)")
        ->capture_default_str();
    cmd->add_option("--imu-port", o->imu_port, "Ouster IMU packets (0: off)")
        ->capture_default_str();
    cmd->add_option("--source-port", o->source_port,
                    "Local port to send data from (a Velodyne sends 2368 -> 2368); 0: any");
    cmd->add_option("--return-mode", o->wire.return_mode, "Velodyne: strongest, last or dual")
        ->check(CLI::IsMember({"strongest", "last", "dual"}))
        ->capture_default_str();
    cmd->add_option("--rpm", o->rpm, "Velodyne rotation rate (model's range, e.g. 300-1200)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--profile", o->wire.profile,
                    "Ouster UDP profile: LEGACY, RNG19_RFL8_SIG16_NIR16 or RNG15_RFL8_NIR8")
        ->capture_default_str();
    cmd->add_option("--timestamp-mode", o->wire.timestamp_mode,
                    "Ouster: TIME_FROM_INTERNAL_OSC, TIME_FROM_SYNC_PULSE_IN or TIME_FROM_PTP_1588")
        ->check(CLI::IsMember(
            {"TIME_FROM_INTERNAL_OSC", "TIME_FROM_SYNC_PULSE_IN", "TIME_FROM_PTP_1588"}))
        ->capture_default_str();
    cmd->add_option("--pcap", o->pcap, "Also write the packets to this pcap (ns timestamps)");
    cmd->add_option("--calibration-out", o->calibration_out,
                    "Velodyne calibration YAML (ROS velodyne_pointcloud) or Ouster metadata JSON; "
                    "default: next to --pcap");
    auto* rt =
        cmd->add_flag("--realtime", o->realtime, "Pace packets on the sensor clock (default)");
    cmd->add_flag("--as-fast-as-possible", o->afap, "Do not pace (pcap generation, benchmarks)")
        ->excludes(rt);
    cmd->add_flag("--no-status", o->no_status, "No status line on stderr");
    cmd->add_option("--rt-priority", o->rt_priority,
                    "Send from a SCHED_FIFO thread at this priority (1-99; needs CAP_SYS_NICE): "
                    "tighter pacing on a busy machine")
        ->check(CLI::Range(0, 99));
    add_keep_awake_flag(*cmd, o->keep_awake);
    cmd->callback([o] {
        JobInputs in = o->job;
        if (!o->pose.empty()) {
            if (!in.trajectory.empty())
                throw ConfigError("emulate: give --pose or --trajectory, not both");
            in.trajectory = "static:" + o->pose;
        }
        if (o->to.empty() && o->pcap.empty())
            throw ConfigError("emulate: nothing to do: give --to HOST and/or --pcap FILE");
        const bool is_static =
            in.nav_log.empty() && (in.trajectory.empty() || in.trajectory.rfind("static:", 0) == 0);
        const bool forever = is_static && in.duration.empty();
        if (forever && o->afap)
            throw ConfigError(
                "emulate: --as-fast-as-possible needs --duration (a static pose "
                "otherwise streams until Ctrl-C)");
        if (forever) in.duration = "86400";  // until interrupted (a day at most)
        const bool csv = !is_static && !is_demo_trajectory(in.trajectory);
        const bool start_now = in.start.empty() && !csv;
        if (start_now) in.start = gps_now_spec();

        Job job = load_job(in);
        // Started "now" in real time: the first pulse moves to the host's GPS time ahead of the
        // schedule, so the packets carry CLOCK_REALTIME's time (docs/time.md §1).
        if (start_now && !o->afap) move_start(job, host_gps_time_ahead(kHostClockStartLead));
        wire::prepare_sensor(job.sensor, o->wire, o->rpm);
        if (!o->afap) set_render_lead(job, output::kEmulateRenderLead);
        const bool ouster = job.sensor.wire.family == sensor::WireFamily::Ouster;

        const auto awake = keep_cpus_awake(o->keep_awake && !o->afap, "emulate");
        output::PacketOutputOptions po;
        po.realtime = !o->afap;
        po.pin_cpu = hostclock::sending_cpu_of(awake.get());
        // Packets go to one deadline-ordered sending thread, as a rig's do: the writer hands
        // them over ahead of time, so rendering and encoding never delay a send
        // (docs/benchmarks.md §3.1). A capture alone is paced by the writer.
        std::shared_ptr<udp::SharedSender> sender;
        if (!o->afap && !o->to.empty())
            sender = make_paced_sender(o->rt_priority, awake.get(), "emulate");
        po.shared_sender = sender;
        po.status_line = !o->no_status;
        po.fifo_priority = o->rt_priority;
        po.start_lead = output::kEmulateStartLead;
        po.pcap_path = o->pcap;
        const udp::StreamPorts ports =
            output::sensor_ports(ouster, o->data_port, o->position_port, o->imu_port);
        output::route_streams(po, ports, o->to, o->source_port);
        // The encoder first: it checks the model's settings (rpm range, profile) before any
        // socket or file is opened.
        wire::WireOptions wo = o->wire;
        wo.position_packets = ports.position != 0;
        wo.imu_packets = ports.imu != 0;
        // On the host's clock: the timestamps follow its steps (docs/time.md §1).
        std::optional<hostclock::ClockStepFollower> clock;
        if (start_now && !o->afap) clock.emplace([] { return -host_gps_offset_ns(); });
        po.clock_follower = clock ? &*clock : nullptr;
        wire::WireContext ctx = wire_context(job);
        ctx.clock_step = clock ? &clock->step() : nullptr;
        std::optional<output::PacketOutput> out;
        wire::WireSetup w = wire::make_wire(
            ctx, wo, [&out](const wire::PacketView& p) { (*out)(p); }, o->to);
        out.emplace(po);
        if (start_now && !o->afap)
            out->anchor(job.options.start,
                        job.options.start.time_since_epoch().count() + host_gps_offset_ns());
        std::string side = o->calibration_out;
        if (side.empty() && !o->pcap.empty()) side = default_side_path(o->pcap, w.side_file_ext);
        if (!side.empty()) write_text_file(side, w.side_file, "emulate: " + w.side_file_kind);

        std::fprintf(
            stderr, "mirage emulate: %s %s -> %s%s, %.0f data packets/s%s\n", w.vendor.c_str(),
            job.sensor.name.c_str(),
            o->to.empty() ? "(no network)" : fmt::format("{}:{}", o->to, ports.data).c_str(),
            o->pcap.empty() ? "" : (" + " + o->pcap).c_str(), w.packets_per_second,
            forever ? ", until Ctrl-C" : "");
        const auto& stop = install_stop_signal();
        output::PacketizerSink sink(*w.packetizer);
        const auto stats = render::render(job.setup(), sink, {}, &stop);
        const output::PacketOutputTotals t = out->finish();
        std::printf(
            "mirage emulate: %llu packets (%.2f MB) in %.3f s, %llu points from %llu pulses; "
            "sent %llu, failed sends %llu, pcap %llu; lateness p50 %.0f µs, p99 %.0f µs, worst "
            "%.0f µs, late %llu%s%s%s\n",
            static_cast<unsigned long long>(t.packets), double(t.bytes) / 1e6, t.seconds,
            static_cast<unsigned long long>(stats.points),
            static_cast<unsigned long long>(stats.pulses), static_cast<unsigned long long>(t.sent),
            static_cast<unsigned long long>(t.send_failed),
            static_cast<unsigned long long>(t.pcap_packets), double(t.p50.count()) / 1e3,
            double(t.p99.count()) / 1e3, double(t.worst_late.count()) / 1e3,
            static_cast<unsigned long long>(t.late), t.paced ? ", " : "",
            output::late_share_text(t).c_str(), stop.load() ? " (interrupted)" : "");
        if (!side.empty()) std::printf("  wrote %s %s\n", w.side_file_kind.c_str(), side.c_str());
        print_clock_steps(stdout, clock ? &*clock : nullptr);
    });
}

}  // namespace mirage::hil
