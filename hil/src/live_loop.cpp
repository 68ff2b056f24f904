// SPDX-License-Identifier: Apache-2.0
#include "live_loop.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navpose/nav_counters.hpp"
#include "mirage/render/pipeline.hpp"

namespace mirage::hil {

navpose::NavFrame live_frame(const Job& job, const std::vector<double>& origin,
                             const std::string& who) {
    if (!origin.empty()) {
        if (origin.size() != 3) throw ConfigError(who + ": --nav-origin expects lat,lon,h");
        return navpose::NavFrame::tangent_plane(origin[0], origin[1], origin[2]);
    }
    return navpose::NavFrame::from_georef(job.scene->georef);
}

std::size_t live_window_pulses(const Job& job, double packets_per_second, core::Nanos delay) {
    const double pulses_per_s =
        double(job.sensor.scan->pulse_count(std::chrono::seconds(10))) / 10.0;
    const std::size_t group = std::max<std::uint32_t>(1, job.sensor.scan->group_size());
    const auto packet = static_cast<std::size_t>(std::llround(pulses_per_s / packets_per_second));
    const std::size_t groups = std::max<std::size_t>(1, packet / group);
    const double span_s = 1.0 / packets_per_second,
                 delay_s = std::chrono::duration<double>(delay).count();
    const double wanted = delay_s > 0.0 ? std::ceil(span_s / (2.0 * delay_s)) : 1.0;
    std::size_t windows = static_cast<std::size_t>(std::clamp(wanted, 1.0, double(groups)));
    while (groups % windows != 0) ++windows;  // so a packet's last pulse ends a window
    return groups / windows * group;
}

std::optional<core::GpsTime> wait_first_pose(const navpose::PoseBuffer& poses,
                                             const navio::NavInput& nav, const std::string& nav_uri,
                                             double timeout_s, const std::atomic<bool>& stop,
                                             const std::string& who) {
    if (await_first_pose(poses, stop, timeout_s)) return poses.newest();
    if (stop.load()) return std::nullopt;
    const auto c = nav.counters();
    throw FirstPoseTimeout(
        fmt::format("{}: no full pose (position + attitude + time) from '{}' within {} s "
                    "({}; bytes skipped {}{}{})",
                    who, nav_uri, timeout_s, navpose::nav_counters_line(c.decode, c.track),
                    c.decode.garbage_bytes, c.detail.empty() ? "" : "; ", c.detail));
}

bool await_first_pose(const navpose::PoseBuffer& poses, const std::atomic<bool>& stop,
                      double seconds) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<int>(seconds * 1e3));
    while (!stop.load() && !poses.newest() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return !stop.load() && poses.newest().has_value();
}

LiveOptions before_first_pose(LiveOptions lo, std::int64_t host_offset_ns) {
    lo.until_first_pose = true;
    lo.host_clock_offset_ns = host_offset_ns;
    lo.message_latency = false;
    return lo;
}

LiveTotals stream_before_first_pose(Job& job, output::PacketOutput& out, navio::NavInput& nav,
                                    const navpose::PoseBuffer& poses, LiveOptions lo,
                                    const wire::WireOptions& wo, const std::string& to,
                                    core::Nanos delay, const std::atomic<bool>& stop) {
    const std::int64_t off = host_gps_offset_ns();
    job.options.start = host_gps_time_ahead(kHostPulse0Lead);
    LiveSession session(job, out, nav, poses, before_first_pose(lo, off));
    wire::WireContext ctx = wire_context(job);
    ctx.gps_locked = false;  // no fix yet: PPS absent, $GPRMC void
    wire::WireSetup w = wire::make_wire(
        ctx, wo, [&](const wire::PacketView& p) { session.on_packet(p); }, to);
    out.anchor(job.options.start,
               job.options.start.time_since_epoch().count() + off + delay.count());
    LiveTotals t =
        session.run(*w.packetizer, live_window_pulses(job, w.packets_per_second, delay), stop);
    w.packetizer->finish();
    return t;
}

std::int64_t live_pulse0_ns(const navio::NavInput& nav) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const std::int64_t ins_now = hostclock::monotonic_ns() - nav.offset_ns().value_or(0);
    return (ins_now / 1'000'000 + 20) * 1'000'000;
}

LiveSession::LiveSession(Job& job, output::PacketOutput& out, navio::NavInput& nav,
                         const navpose::PoseBuffer& poses, LiveOptions options)
    : job_(job), out_(out), nav_(nav), poses_(poses), opt_(options) {}

void LiveSession::on_packet(const wire::PacketView& p) {
    out_(p);
    ++tot_.packets;
    tot_.bytes += p.bytes.size();
    if (p.stream != wire::Stream::Data) return;
    // Sent (paced here) or handed to a sending thread, the packet leaves at its deadline or at
    // once when later; the sender's own lateness is reported apart (docs/live-navigation.md §10).
    latency_.data_packet_sent(std::max(hostclock::monotonic_ns(), out_.deadline_ns(p.time)));
}

LiveTotals LiveSession::run(wire::Packetizer& packetizer, std::size_t pulses_per_window,
                            const std::atomic<bool>& stop) {
    const core::GpsTime start = job_.options.start;
    const auto& scan = *job_.sensor.scan;
    render::WindowRenderer wr(job_.setup());
    std::vector<core::PointRecord> pts;
    render::RenderStats rstats;
    const std::int64_t t_begin = hostclock::monotonic_ns();
    next_status_ns_ = t_begin + 1'000'000'000;
    bool stale = false;
    std::string stale_reason;
    sensor::PulseSpec spec_first{}, spec_last{};
    std::optional<core::Pose> frozen;  // the pose held while navigation is faulted frozen
    if (opt_.message_latency) (void)nav_.take_applied();  // the backlog is not latency

    for (std::uint64_t k = 0; !stop.load(); k += pulses_per_window) {
        if (opt_.until_first_pose && poses_.newest()) break;
        scan.pulses(k, 1, &spec_first);
        scan.pulses(k + pulses_per_window - 1, 1, &spec_last);
        const core::GpsTime t_first = start + core::Nanos(spec_first.t_ns);
        const core::GpsTime t_last = start + core::Nanos(spec_last.t_ns);
        if (opt_.duration.count() > 0 && t_first - start >= opt_.duration) break;
        const std::int64_t off =
            opt_.host_clock_offset_ns ? *opt_.host_clock_offset_ns : nav_.offset_ns().value_or(0);
        const std::int64_t wake_ns = t_last.time_since_epoch().count() + off;
        send_side_packets(packetizer, t_last, wake_ns);
        hostclock::sleep_until_monotonic(wake_ns);

        pts.clear();
        ++tot_.windows;
        const control::FaultSettings fault =
            opt_.faults ? opt_.faults->load() : control::FaultSettings{};
        auto win =
            fault.stale_nav ? std::nullopt : poses_.window(t_first, t_last, (t_last - t_first) / 2);
        // After the window: every message it used has been listed by then (NavInput lists a
        // message before its samples reach the pose buffer).
        if (opt_.message_latency) latency_.applied(nav_.take_applied());
        if (!fault.freeze_nav) frozen.reset();
        if (fault.freeze_nav && !frozen && win) frozen = win->trajectory.at(t_first);
        // A frozen INS repeats its last pose whatever arrives; stale navigation injected over
        // it still wins (docs/control.md §5).
        if (frozen && !fault.stale_nav) {
            wr.render(core::Trajectory::fixed(*frozen), k, pulses_per_window, pts, rstats);
            stale = false;
        } else if (win) {
            wr.render(win->trajectory, k, pulses_per_window, pts, rstats);
            if (opt_.message_latency) latency_.rendered(win->used);
            stale = false;
        } else {
            ++tot_.stale_windows;
            if (!stale) stale_periods_.store(++tot_.stale_periods, std::memory_order_relaxed);
            stale = true;
            const auto q = poses_.at(t_last);
            stale_reason =
                fault.stale_nav ? "stale navigation injected"
                : q.status == navpose::PoseStatus::Empty
                    ? "no full pose yet (no fix)"
                    : fmt::format("no navigation for {:.0f} ms", double(q.age.count()) / 1e6);
        }
        tot_.points += pts.size();
        packetizer.add(pts);
        packetizer.advance_to(k + pulses_per_window);
        if (opt_.status_line) print_status(t_last, stale, stale_reason);
    }
    if (opt_.status_line) std::fprintf(stderr, "\n");
    if (opt_.message_latency) latency_.applied(nav_.take_applied());
    const navio::MessageLatency::Unused unused = latency_.unused();
    tot_.latency = latency_.latency();
    tot_.messages = latency_.messages();
    tot_.superseded = unused.superseded;
    tot_.waiting_at_end = unused.waiting;
    tot_.seconds = double(hostclock::monotonic_ns() - t_begin) / 1e9;
    return tot_;
}

void LiveSession::send_side_packets(wire::Packetizer& packetizer, core::GpsTime t_last,
                                    std::int64_t wake_ns) {
    if (out_.hands_over_ahead()) {
        packetizer.emit_side_packets_until(t_last);
        return;
    }
    // Paced here: only those due before the loop wakes, or it would wake late. A packet's
    // deadline lies `lead` (the pipeline delay) after its sensor time.
    const core::Nanos lead(out_.deadline_ns(t_last) - wake_ns);
    packetizer.emit_side_packets_until(t_last - lead);
}

void LiveSession::print_status(core::GpsTime t_last, bool stale, const std::string& stale_reason) {
    const std::int64_t now = hostclock::monotonic_ns();
    if (now < next_status_ns_) return;
    const auto nc = nav_.counters();
    const auto newest = poses_.newest();
    const double age_ms = newest ? double((t_last - *newest).count()) / 1e6 : 0.0;
    std::fprintf(stderr,
                 "\rlive: nav %llu msg/s, rejected %llu, pose age %.1f ms, stale %llu "
                 "periods%s%s | %llu pkt/s %.2f Mbit/s | INS->packet p99 %.2f ms   ",
                 static_cast<unsigned long long>(nc.track.applied - nav_at_status_),
                 static_cast<unsigned long long>(nc.decode.rejected() + nc.track.rejected()),
                 age_ms, static_cast<unsigned long long>(tot_.stale_periods),
                 stale ? " — STALE: " : "", stale ? stale_reason.c_str() : "",
                 static_cast<unsigned long long>(tot_.packets - packets_at_status_),
                 double(tot_.bytes - bytes_at_status_) * 8e-6,
                 double(latency_.latency().percentile(0.99).count()) / 1e6);
    std::fflush(stderr);
    nav_at_status_ = nc.track.applied;
    packets_at_status_ = tot_.packets;
    bytes_at_status_ = tot_.bytes;
    next_status_ns_ += 1'000'000'000;
    if (next_status_ns_ < now) next_status_ns_ = now + 1'000'000'000;
}

}  // namespace mirage::hil
