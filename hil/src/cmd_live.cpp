// SPDX-License-Identifier: Apache-2.0
// `mirage live`: the sensor's pose comes from an INS in real time (NMEA, NovAtel, NCOM, OxTS or
// SBG CAN); what a lidar on that vehicle would see goes out as vendor UDP packets.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "job.hpp"
#include "keep_awake_option.hpp"
#include "live_loop.hpp"
#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navio/fake_ins.hpp"
#include "mirage/navio/nav_input.hpp"
#include "mirage/navio/nav_recorder.hpp"
#include "mirage/output/packet_output.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/wire/setup.hpp"
#include "paced_sender.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {

void register_live(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "live", "Emulate a lidar in real time with the pose from an INS (serial, TCP, UDP, CAN)");
    struct Opts {
        JobInputs job;
        std::string nav;
        std::string to;
        std::uint16_t data_port = 0, position_port = 8308, imu_port = 7503;
        wire::WireOptions wire;
        double rpm = 0;
        std::string pcap;
        std::string duration;
        double max_extrapolation_ms = 50, max_jump_m = 20, pipeline_delay_us = 250;
        double first_nav_timeout_s = 0, undulation_m = 0;
        std::vector<double> nav_origin;
        std::string fake_ins;
        double fake_ins_rate = 100;
        bool no_status = false;
        int rt_priority = 0;
        bool keep_awake = false;
        std::string pose_log, nav_record, nav_record_ifname, nav_date = "host";
    };
    auto o = std::make_shared<Opts>();
    add_job_options(*cmd, o->job, false);
    cmd->add_option("--sensor", o->job.sensor, "Sensor preset (Velodyne or Ouster)")
        ->capture_default_str();
    cmd->add_option("--nav", o->nav,
                    "Navigation input <protocol>:<transport>: nmea:/dev/ttyUSB0?baud=115200, "
                    "novatel:tcp://host:port, ncom:udp://:3000, oxts-can:socketcan:can0, "
                    "sbg-can:slcan:/dev/ttyACM0, oxts-can:gsusb:1d50:606f, oxts-can:memory:x, "
                    "dis:udp://:3000?exercise=1&entity=1.2.3&timeout=12")
        ->required();
    cmd->add_option("--to", o->to, "Destination IPv4 host of the lidar packets");
    cmd->add_option("--data-port", o->data_port, "Lidar data port (default 2368 / 7502)");
    cmd->add_option("--position-port", o->position_port, "Velodyne position packets (0: off)")
        ->capture_default_str();
    cmd->add_option("--imu-port", o->imu_port, "Ouster IMU packets (0: off)")
        ->capture_default_str();
    cmd->add_option("--return-mode", o->wire.return_mode, "Velodyne: strongest, last or dual")
        ->check(CLI::IsMember({"strongest", "last", "dual"}))
        ->capture_default_str();
    cmd->add_option("--rpm", o->rpm, "Velodyne rotation rate")->check(CLI::NonNegativeNumber);
    cmd->add_option("--profile", o->wire.profile, "Ouster UDP profile")->capture_default_str();
    cmd->add_option("--timestamp-mode", o->wire.timestamp_mode,
                    "Ouster: TIME_FROM_INTERNAL_OSC, TIME_FROM_SYNC_PULSE_IN or TIME_FROM_PTP_1588")
        ->check(CLI::IsMember(
            {"TIME_FROM_INTERNAL_OSC", "TIME_FROM_SYNC_PULSE_IN", "TIME_FROM_PTP_1588"}))
        ->capture_default_str();
    cmd->add_option("--pcap", o->pcap, "Also write the packets to this pcap");
    cmd->add_option("--duration", o->duration, "Seconds to run (default: until Ctrl-C)");
    cmd->add_option("--max-extrapolation-ms", o->max_extrapolation_ms,
                    "Beyond the newest navigation message, poses are extrapolated this long; "
                    "then the state is stale and no returns are sent")
        ->capture_default_str();
    cmd->add_option("--max-jump-m", o->max_jump_m,
                    "Reject positions further than this from the predicted one")
        ->capture_default_str();
    cmd->add_option("--pipeline-delay-us", o->pipeline_delay_us,
                    "Packets leave at firing time + this (room to render a packet)")
        ->capture_default_str();
    cmd->add_option("--first-nav-timeout", o->first_nav_timeout_s,
                    "Send nothing until the first full pose and fail without one within this many "
                    "seconds (default 0: stream without returns until it comes)")
        ->check(CLI::Range(0.0, 3600.0))
        ->capture_default_str();
    cmd->add_option("--undulation", o->undulation_m,
                    "Geoid height added to heights an INS reports above MSL")
        ->capture_default_str();
    cmd->add_option("--nav-origin", o->nav_origin,
                    "lat,lon,h of the scene origin (local tangent plane), for scenes without a "
                    "UTM/UPS georeference")
        ->delimiter(',');
    cmd->add_option("--fake-ins", o->fake_ins,
                    "Also run a fake INS in this process on the --nav transport, following this "
                    "trajectory (for memory: CAN buses and demos)");
    cmd->add_option("--fake-ins-rate", o->fake_ins_rate, "Fake INS epochs per second")
        ->capture_default_str();
    cmd->add_option("--pose-log", o->pose_log,
                    "Write every pose sample applied (position and attitude tracks, INS GPS "
                    "time, local and as received) to this CSV");
    cmd->add_option("--nav-record", o->nav_record,
                    "Record the navigation input as it arrived: raw bytes for serial/TCP/UDP "
                    "protocols (.nmea, .bin), a candump -L log for CAN");
    cmd->add_option("--nav-record-ifname", o->nav_record_ifname,
                    "Interface name in the candump log (default: from the bus spec, e.g. can0)");
    cmd->add_option("--nav-date", o->nav_date,
                    "NMEA: UTC date assumed until an RMC/ZDA gives one: host (today), stream "
                    "(drop sentences before the stream's first date; for recorded logs) or "
                    "YYYY-MM-DD")
        ->capture_default_str();
    cmd->add_flag("--no-status", o->no_status, "No status line");
    cmd->add_option("--rt-priority", o->rt_priority, "SCHED_FIFO priority of the sending thread")
        ->check(CLI::Range(0, 99));
    add_keep_awake_flag(*cmd, o->keep_awake);
    cmd->callback([o] {
        JobInputs in = o->job;
        in.trajectory = "static:0,0,0";
        in.duration = "1";
        Job job = load_job(in);
        wire::prepare_sensor(job.sensor, o->wire, o->rpm);
        const bool ouster = job.sensor.wire.family == sensor::WireFamily::Ouster;
        const navpose::NavFrame frame = live_frame(job, o->nav_origin, "live");
        const navproto::NavUri uri = navproto::parse_nav_uri(o->nav);
        if (uri.protocol == navproto::NavProtocol::Dis && !o->nav_record.empty())
            throw ConfigError(
                "live: --nav-record keeps a byte stream, and DIS PDUs need their datagram "
                "boundaries: record the DIS stream with `mirage record` (a pcap)");

        navpose::PoseBufferConfig pc;
        pc.max_extrapolation =
            core::Nanos(static_cast<std::int64_t>(o->max_extrapolation_ms * 1e6));
        navpose::PoseBuffer poses(pc);
        const auto& stop = install_stop_signal();
        const auto awake = keep_cpus_awake(o->keep_awake, "live");

        // In-process fake INS (memory buses, demos): opened before the reader so no frame is lost.
        std::unique_ptr<core::Trajectory> fake_traj;
        std::unique_ptr<can::CanBus> fake_bus;
        std::unique_ptr<bytestream::ByteStream> fake_stream;
        std::thread fake_thread;
        std::atomic<bool> fake_stop{false};
        if (!o->fake_ins.empty()) {
            JobInputs fi = in;
            fi.trajectory = o->fake_ins;
            fi.duration.clear();
            fake_traj = std::make_unique<core::Trajectory>(
                load_job_with_scene(fi, job.scene, 0, false).trajectory);
            if (navproto::is_can(uri.protocol))
                fake_bus = can::open_can_bus(uri.transport);
            else
                throw ConfigError(
                    "live: --fake-ins runs in-process on CAN buses (e.g. "
                    "oxts-can:memory:x); for serial/UDP run `mirage fake-ins`");
        }
        // Recorders: opened before the nav thread starts, closed after it stops; a write error
        // fails the command at the end (the files keep whole lines only).
        std::unique_ptr<navio::PoseLog> pose_log;
        std::unique_ptr<navio::NavRecorder> nav_record;
        if (!o->pose_log.empty()) pose_log = std::make_unique<navio::PoseLog>(o->pose_log);
        if (!o->nav_record.empty())
            nav_record = std::make_unique<navio::NavRecorder>(
                o->nav_record,
                navproto::is_can(uri.protocol)
                    ? (o->nav_record_ifname.empty() ? navio::candump_ifname(uri.transport)
                                                    : o->nav_record_ifname)
                    : std::string());
        navio::NavInputOptions nio;
        nio.mapper.undulation_m = o->undulation_m;
        nio.mapper.gate.max_jump_m = o->max_jump_m;
        nio.nmea_date = o->nav_date;
        nio.pose_log = pose_log.get();
        nio.record = nav_record.get();
        navio::NavInput nav(uri, frame, poses, nio);
        // Stops the nav thread, closes the recorders and reports them; throws the first write
        // error. Runs on every way out after the first pose wait (normal end, SIGINT).
        const auto finish_recording = [&] {
            nav.stop();
            std::string err;
            if (pose_log) {
                if (!pose_log->close() && err.empty()) err = pose_log->error();
                std::printf("pose log: %llu samples -> %s\n",
                            static_cast<unsigned long long>(pose_log->rows()), o->pose_log.c_str());
            }
            if (nav_record) {
                if (!nav_record->close() && err.empty()) err = nav_record->error();
                std::printf("nav record: %llu %s (%llu bytes) -> %s\n",
                            static_cast<unsigned long long>(nav_record->units()),
                            nav_record->is_candump() ? "frames (candump -L)" : "chunks (raw)",
                            static_cast<unsigned long long>(nav_record->bytes_written()),
                            o->nav_record.c_str());
            }
            if (const auto bc = nav.bus_counters())
                std::printf(
                    "nav bus: rx frames %llu, error frames %llu, bus-off %llu, "
                    "malformed %llu\n",
                    static_cast<unsigned long long>(bc->rx_frames),
                    static_cast<unsigned long long>(bc->error_frames),
                    static_cast<unsigned long long>(bc->bus_off),
                    static_cast<unsigned long long>(bc->malformed));
            std::fflush(stdout);
            if (!err.empty()) throw IoError(err);
        };
        nav.start();
        if (fake_traj) {
            navio::FakeInsConfig fc;
            fc.protocol = uri.protocol;
            fc.rate_hz = o->fake_ins_rate;
            const core::GpsTime fake_t0 =
                navio::fake_ins_start(o->fake_ins_rate, std::chrono::milliseconds(200));
            std::printf("fake-ins: %s in-process on %s t0 gps:%lld.%09lld\n",
                        to_string(uri.protocol).c_str(), uri.transport.c_str(),
                        static_cast<long long>(fake_t0.time_since_epoch().count() / 1'000'000'000),
                        static_cast<long long>(fake_t0.time_since_epoch().count() % 1'000'000'000));
            std::fflush(stdout);
            fake_thread = std::thread([&, frame, fc, fake_t0] {
                navio::FakeIns ins(*fake_traj, frame, fc);
                ins.run(nullptr, fake_bus.get(), fake_t0, fake_stop);
            });
        }
        struct JoinFake {
            std::atomic<bool>& s;
            std::thread& t;
            ~JoinFake() {
                s = true;
                if (t.joinable()) t.join();
            }
        } join_fake{fake_stop, fake_thread};

        std::fprintf(stderr, "mirage live: %s %s, waiting for navigation on %s%s\n",
                     ouster ? "ouster" : "velodyne", job.sensor.name.c_str(), o->nav.c_str(),
                     nav.udp_port() ? fmt::format(" (udp port {})", nav.udp_port()).c_str() : "");
        std::fflush(stderr);
        output::PacketOutputOptions po;
        po.realtime = true;
        po.status_line = false;
        po.fifo_priority = o->rt_priority;
        // One deadline-ordered sending thread, as emulate and rig: the loop hands packets over
        // before their send times and goes on rendering (docs/live-navigation.md §1). A capture
        // alone is paced by the loop.
        if (!o->to.empty())
            po.shared_sender = make_paced_sender(o->rt_priority, awake.get(), "live");
        po.pcap_path = o->pcap;
        const udp::StreamPorts ports =
            output::sensor_ports(ouster, o->data_port, o->position_port, o->imu_port);
        output::route_streams(po, ports, o->to);
        wire::WireOptions wo = o->wire;
        wo.position_packets = ports.position != 0;
        wo.imu_packets = ports.imu != 0;
        output::PacketOutput out(po);
        // The loop too must wake on time (it renders a window once its last firing has passed):
        // it runs on the CPU kept awake, beside the sending thread. Pinned here, after the
        // navigation threads started, so they do not inherit the pin.
        if (std::string why;
            awake && !hostclock::pin_current_thread(hostclock::sending_cpu_of(awake.get()), why))
            std::fprintf(stderr, "mirage live: render loop not pinned to %s\n", why.c_str());
        const core::Nanos delay(static_cast<std::int64_t>(o->pipeline_delay_us * 1e3));
        LiveOptions lo;
        lo.status_line = !o->no_status;
        if (!o->duration.empty()) lo.duration = parse_seconds(o->duration, "--duration");
        // Without --first-nav-timeout the sensor streams without returns until the first full
        // pose, as a unit spins before GPS lock; with it, it sends nothing until then and fails
        // when none comes in time (docs/live-navigation.md §1).
        bool stop_after_first_phase = false;  // the duration passed before the first pose
        if (o->first_nav_timeout_s > 0) {
            if (!wait_first_pose(poses, nav, o->nav, o->first_nav_timeout_s, stop, "live")) {
                finish_recording();
                return;
            }
        } else if (!await_first_pose(poses, stop, kFirstPoseSettleS) && !stop.load()) {
            std::fprintf(stderr,
                         "mirage live: no full pose yet: streaming without returns on the host "
                         "clock until one arrives\n");
            const LiveTotals t1 =
                stream_before_first_pose(job, out, nav, poses, lo, wo, o->to, delay, stop);
            std::printf(
                "mirage live: before the first pose: %llu packets without returns in "
                "%.3f s\n",
                static_cast<unsigned long long>(t1.packets), t1.seconds);
            std::fflush(stdout);
            if (!poses.newest()) {
                stop_after_first_phase = true;  // the duration passed first
            } else if (lo.duration.count() > 0) {
                lo.duration = std::max(
                    core::Nanos(1),
                    lo.duration - core::Nanos(static_cast<std::int64_t>(t1.seconds * 1e9)));
            }
        }
        if (stop.load() || stop_after_first_phase) {
            (void)out.finish();
            finish_recording();
            return;
        }
        const std::optional<core::GpsTime> first = poses.newest();
        const std::int64_t t0 = live_pulse0_ns(nav);
        job.options.start = core::GpsTime(core::Nanos(t0));
        LiveSession session(job, out, nav, poses, lo);
        wire::WireSetup w = wire::make_wire(
            wire_context(job), wo, [&](const wire::PacketView& p) { session.on_packet(p); }, o->to);
        out.anchor(job.options.start, t0 + nav.offset_ns().value_or(0) + delay.count());
        const std::size_t window = live_window_pulses(job, w.packets_per_second, delay);
        std::fprintf(
            stderr,
            "mirage live: first pose at gps:%.3f; pulse 0 at gps:%.3f; %zu pulses "
            "per window, %d sub-rays -> %s\n",
            double(first->time_since_epoch().count()) / 1e9, double(t0) / 1e9, window,
            job.sensor.beam.sub_rays,
            o->to.empty() ? "(no network)" : fmt::format("{}:{}", o->to, ports.data).c_str());
        LiveTotals t = session.run(*w.packetizer, window, stop);
        w.packetizer->finish();
        const output::PacketOutputTotals pt = out.finish();
        nav.stop();
        const auto nc = nav.counters();
        std::printf(
            "mirage live: %llu packets (%.2f MB) in %.3f s, %llu points, %d sub-rays; windows "
            "%llu, stale windows %llu in %llu periods; %s%s%s; INS->packet latency p50 %.3f ms p99 "
            "%.3f ms max %.3f ms (%llu messages; never in a packet: %llu superseded, %llu "
            "waiting at the end); packet lateness p99 %.0f µs, late %llu, failed sends %llu%s%s\n",
            static_cast<unsigned long long>(t.packets), double(t.bytes) / 1e6, t.seconds,
            static_cast<unsigned long long>(t.points), job.sensor.beam.sub_rays,
            static_cast<unsigned long long>(t.windows),
            static_cast<unsigned long long>(t.stale_windows),
            static_cast<unsigned long long>(t.stale_periods),
            navpose::nav_counters_line(nc.decode, nc.track).c_str(), nc.detail.empty() ? "" : "; ",
            nc.detail.c_str(), double(t.latency.percentile(0.5).count()) / 1e6,
            double(t.latency.percentile(0.99).count()) / 1e6,
            double(t.latency.worst().count()) / 1e6,
            static_cast<unsigned long long>(t.latency.count()),
            static_cast<unsigned long long>(t.superseded),
            static_cast<unsigned long long>(t.waiting_at_end), double(pt.p99.count()) / 1e3,
            static_cast<unsigned long long>(pt.late),
            static_cast<unsigned long long>(pt.send_failed), pt.paced ? "; " : "",
            output::late_share_text(pt).c_str());
        std::fflush(stdout);
        finish_recording();
    });
}

}  // namespace mirage::hil
