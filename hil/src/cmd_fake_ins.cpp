// SPDX-License-Identifier: Apache-2.0
// `mirage fake-ins`: the loopback harness's stand-in for an INS — a scripted trajectory sent in
// real time as NMEA, NovAtel, NCOM, OxTS CAN or SBG CAN on a pty, UDP, slcan pty or CAN bus.
#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "job.hpp"
#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navcan/slcan.hpp"
#include "mirage/navio/fake_ins.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navproto/nav_log.hpp"
#include "stop_signal.hpp"

namespace mirage::hil {
namespace {

// The device side of slcan on a pty: CAN frames go out as Lawicel lines, and every command the
// host sends (C, S6, O, …) is acknowledged with CR as a CANable does.
class SlcanDevice : public can::CanBus {
  public:
    explicit SlcanDevice(bytestream::Pty pty) : pty_(std::move(pty)) {
        reader_ = std::thread([this] { answer(); });
    }
    ~SlcanDevice() override {
        stop_ = true;
        if (reader_.joinable()) reader_.join();
    }
    bool send(const nav::CanFrame& f) override {
        const std::string line = navcan::slcan_encode(f);
        std::lock_guard lk(mu_);
        const bool ok = pty_.master->write(
            std::span(reinterpret_cast<const std::uint8_t*>(line.data()), line.size()));
        ok ? ++c_.tx_frames : ++c_.tx_failed;
        return ok;
    }
    can::RxStatus receive(nav::CanFrame&, std::int64_t&, std::chrono::nanoseconds t) override {
        std::this_thread::sleep_for(t);
        return can::RxStatus::Timeout;
    }
    can::BusCounters counters() const override { return c_; }
    std::string name() const override { return "slcan-device:" + pty_.slave_path; }

  private:
    void answer() {
        std::array<std::uint8_t, 256> buf{};
        while (!stop_) {
            std::size_t n = 0;
            std::int64_t ns = 0;
            if (pty_.master->read(buf, n, ns, std::chrono::milliseconds(50)) !=
                bytestream::ReadStatus::Data)
                continue;
            for (std::size_t i = 0; i < n; ++i) {
                if (buf[i] != '\r') continue;
                const std::uint8_t ok = '\r';
                std::lock_guard lk(mu_);
                pty_.master->write(std::span(&ok, 1));
            }
        }
    }
    bytestream::Pty pty_;
    std::mutex mu_;
    std::atomic<bool> stop_{false};
    std::thread reader_;
    can::BusCounters c_;
};

// "pty[:LINK]" / "slcan-pty[:LINK]": a symlink LINK -> the pty's slave, so a reader can be
// started with a fixed path.
std::string link_of(const std::string& to, const std::string& kind) {
    return to.size() > kind.size() + 1 ? to.substr(kind.size() + 1) : std::string();
}

void make_link(const std::string& link, const std::string& target) {
    if (link.empty()) return;
    std::error_code ec;
    // Replaces a link left by an earlier run, never a file or device the path happens to name.
    const auto st = std::filesystem::symlink_status(link, ec);
    if (std::filesystem::exists(st) && !std::filesystem::is_symlink(st))
        throw IoError("fake-ins: cannot create link '" + link +
                      "': something other than a link is there");
    std::filesystem::remove(link, ec);
    std::filesystem::create_symlink(target, link, ec);
    if (ec) throw IoError("fake-ins: cannot create link '" + link + "': " + ec.message());
}

// --log: the frame the rules measure jumps in, a tangent plane at the log's first fix (metres
// differ from a scene's UTM grid by its scale factor, < 0.1 %).
navpose::NavFrame first_fix_frame(const navproto::NavLog& log) {
    for (const auto& s : log.samples)
        if (s.has(nav::NavSample::kPosition) && std::isfinite(s.lat_deg) &&
            std::isfinite(s.lon_deg) && std::isfinite(s.height_m) && std::abs(s.lat_deg) <= 90 &&
            std::abs(s.lon_deg) <= 180)
            return navpose::NavFrame::tangent_plane(s.lat_deg, s.lon_deg, s.height_m);
    return navpose::NavFrame::tangent_plane(0, 0, 0);
}

}  // namespace

void register_fake_ins(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "fake-ins", "Stand in for an INS: send a trajectory in real time as navigation messages");
    struct Opts {
        JobInputs job;
        std::string protocol = "nmea";
        std::string to = "pty";
        double rate = 100;
        std::string duration;
        std::vector<std::string> silence;
        std::string jump_at, backwards_at, nan_at;
        std::uint64_t corrupt_every = 0;
        std::string log;
        double speed = 1.0;
        std::string nav_date;
        double max_jump_m = 20;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--trajectory", o->job.trajectory,
                    "Trajectory CSV, 'static:x,y,z[,roll,pitch,yaw]' or 'demo-car' (played from "
                    "its start at the moment the command starts)");
    cmd->add_option("--log", o->log,
                    "Replay a recorded navigation log with its own timing instead of a "
                    "trajectory: raw NMEA/NovAtel/NCOM bytes (message times) or candump -L for "
                    "the CAN protocols (log timestamps)");
    cmd->add_option("--speed", o->speed, "--log: replay speed factor (2 = twice as fast)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--nav-date", o->nav_date,
                    "--log, NMEA without RMC/ZDA: the log's UTC date YYYY-MM-DD (default: today)");
    cmd->add_option("--max-jump-m", o->max_jump_m,
                    "--log: the rule `mirage live --max-jump-m` applies, for the report of what "
                    "live would reject in the log (the log is replayed as recorded)")
        ->capture_default_str();
    cmd->add_option("--scene", o->job.scene, "Scene whose georeference maps local to WGS84")
        ->capture_default_str();
    cmd->add_option("--protocol", o->protocol,
                    "nmea, novatel, ncom, oxts-can, sbg-can or dis (entity 1.1.1, exercise 1)")
        ->capture_default_str();
    cmd->add_option("--to", o->to,
                    "pty[:LINK], udp://host:port, tcp is not offered, slcan-pty[:LINK], "
                    "socketcan:<if>, gsusb:<vid>:<pid>")
        ->capture_default_str();
    cmd->add_option("--rate", o->rate, "Epochs per second")->capture_default_str();
    cmd->add_option("--duration", o->duration, "Seconds to run (default: until Ctrl-C)");
    cmd->add_option("--silence", o->silence,
                    "Fault: no messages from S for L seconds after the start (S,L)")
        ->delimiter(',')
        ->expected(2);
    cmd->add_option("--jump-at", o->jump_at, "Fault: one epoch's position 100 m off at S seconds");
    cmd->add_option("--backwards-at", o->backwards_at,
                    "Fault: one epoch stamped 1 s in the past at S seconds");
    cmd->add_option("--nan-at", o->nan_at, "Fault: one epoch with a NaN latitude at S seconds");
    cmd->add_option("--corrupt-every", o->corrupt_every,
                    "Fault: flip a byte in every N-th message (serial/UDP protocols)");
    cmd->callback([o] {
        const navproto::NavProtocol proto = navproto::parse_nav_protocol(o->protocol);
        if (!(o->rate > 0 && o->rate <= 1000))
            throw ConfigError("fake-ins: --rate must be in (0, 1000] Hz");
        if (o->log.empty() == o->job.trajectory.empty())
            throw ConfigError("fake-ins: give --trajectory or --log (one of them)");
        std::optional<navproto::NavLog> log;
        std::optional<Job> job;
        if (!o->log.empty()) {
            navproto::NavLogOptions lo;
            lo.nmea_date = o->nav_date;
            log = navproto::read_nav_log(o->log, proto, lo);
            std::printf("fake-ins: %s\n", navproto::nav_log_summary(*log).c_str());
            // Replayed byte for byte, faults included (that is what a receiver is tested with);
            // what `mirage live` would refuse in it, counted by the same decoder and rules:
            navpose::NavMapperConfig mc;
            mc.gate.max_jump_m = o->max_jump_m;
            const auto tracks = navproto::nav_log_tracks(*log, first_fix_frame(*log), mc);
            std::printf("fake-ins: as live counts it: %s\n",
                        navpose::nav_counters_line(log->stats.decode, tracks.counters).c_str());
            if (log->stats.messages == 0)
                throw ConfigError("fake-ins: nav log '" + o->log + "': nothing to replay");
        } else {
            JobInputs in = o->job;
            double scene_s = 0;
            auto scene = load_scene_timed(in.scene, scene_s);
            job.emplace(load_job_with_scene(in, scene, scene_s, false));
        }
        navio::FakeInsConfig fc;
        fc.protocol = proto;
        fc.rate_hz = o->rate;
        if (!o->duration.empty()) fc.duration = parse_seconds(o->duration, "--duration");
        if (!o->silence.empty()) {
            fc.faults.silence_at = parse_seconds(o->silence[0], "--silence");
            fc.faults.silence_for = parse_seconds(o->silence[1], "--silence");
        }
        if (!o->jump_at.empty()) fc.faults.jump_at = parse_seconds(o->jump_at, "--jump-at");
        if (!o->backwards_at.empty())
            fc.faults.backwards_at = parse_seconds(o->backwards_at, "--backwards-at");
        if (!o->nan_at.empty()) fc.faults.nan_at = parse_seconds(o->nan_at, "--nan-at");
        fc.faults.corrupt_every = o->corrupt_every;

        std::unique_ptr<bytestream::ByteStream> stream;
        std::unique_ptr<can::CanBus> bus;
        std::string where;
        const std::string& to = o->to;
        if (to.rfind("memory", 0) == 0)
            throw ConfigError(
                "fake-ins: a memory: bus lives in one process; use `mirage live "
                "--nav oxts-can:memory:x --fake-ins TRAJ`");
        if (navproto::needs_datagrams(proto) && to.rfind("udp://", 0) != 0)
            throw ConfigError("fake-ins: " + o->protocol +
                              " sends UDP datagrams: --to udp://host:port");
        if (to == "pty" || to.rfind("pty:", 0) == 0) {
            if (navproto::is_can(proto))
                throw ConfigError("fake-ins: CAN protocols need slcan-pty or a bus");
            auto pty = bytestream::open_pty();
            where = pty.slave_path;
            make_link(link_of(to, "pty"), where);
            stream = std::move(pty.master);
        } else if (to == "slcan-pty" || to.rfind("slcan-pty:", 0) == 0) {
            if (!navproto::is_can(proto))
                throw ConfigError("fake-ins: slcan-pty carries CAN protocols only");
            auto pty = bytestream::open_pty();
            where = pty.slave_path;
            make_link(link_of(to, "slcan-pty"), where);
            bus = std::make_unique<SlcanDevice>(std::move(pty));
        } else if (to.rfind("udp://", 0) == 0) {
            if (navproto::is_can(proto))
                throw ConfigError("fake-ins: CAN protocols need a CAN transport");
            stream = bytestream::open_byte_stream(
                to + (to.find('?') == std::string::npos ? "?send" : "&send"));
            where = to;
        } else {
            if (!navproto::is_can(proto))
                throw ConfigError("fake-ins: unknown --to '" + to + "' for " + o->protocol);
            bus = can::open_can_bus(to);
            where = to;
        }
        const auto& stop = install_stop_signal();
        if (log) {
            std::printf("fake-ins: replaying %s (%s) on %s at %gx\n", o->log.c_str(),
                        o->protocol.c_str(), where.c_str(), o->speed);
            std::fflush(stdout);
            const navio::ReplayTotals r = navio::replay_nav_log(
                *log, stream.get(), bus.get(), o->speed, stop,
                hostclock::monotonic_ns() + 200'000'000);  // 200 ms for a reader to attach
            std::printf(
                "fake-ins: replayed %llu messages, %llu bytes, %.3f s of log, %llu "
                "failed writes, worst lateness %.0f us%s\n",
                static_cast<unsigned long long>(r.messages),
                static_cast<unsigned long long>(r.bytes), double(r.span_ns) * 1e-9,
                static_cast<unsigned long long>(r.write_failures), double(r.worst_late_ns) * 1e-3,
                r.interrupted ? " (interrupted)" : "");
            return;
        }
        const navpose::NavFrame frame = navpose::NavFrame::from_georef(job->scene->georef);
        const core::GpsTime t0 = navio::fake_ins_start(o->rate, std::chrono::milliseconds(200));
        std::printf("fake-ins: %s on %s t0 gps:%lld.%09lld\n", o->protocol.c_str(), where.c_str(),
                    static_cast<long long>(t0.time_since_epoch().count() / 1'000'000'000),
                    static_cast<long long>(t0.time_since_epoch().count() % 1'000'000'000));
        std::fflush(stdout);
        navio::FakeIns ins(job->trajectory, frame, fc);
        const navio::FakeInsTotals t = ins.run(stream.get(), bus.get(), t0, stop);
        std::printf(
            "fake-ins: %llu epochs, %llu messages, %llu bytes, %llu failed writes, %llu "
            "epochs skipped behind a blocked output\n",
            static_cast<unsigned long long>(t.epochs), static_cast<unsigned long long>(t.messages),
            static_cast<unsigned long long>(t.bytes),
            static_cast<unsigned long long>(t.write_failures),
            static_cast<unsigned long long>(t.skipped));
        std::printf(
            "fake-ins: faults: %llu epochs silenced, %llu jumps, %llu backwards, %llu NaN, "
            "%llu corrupted messages\n",
            static_cast<unsigned long long>(t.silenced), static_cast<unsigned long long>(t.jumps),
            static_cast<unsigned long long>(t.backwards), static_cast<unsigned long long>(t.nans),
            static_cast<unsigned long long>(t.corrupted));
    });
}

}  // namespace mirage::hil
