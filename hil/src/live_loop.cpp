// SPDX-License-Identifier: Apache-2.0
#include "live_loop.hpp"

#include <fmt/format.h>
#include <time.h>

#include <cstdio>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/render/pipeline.hpp"
#include "mirage/udp/pacer.hpp"

namespace mirage::hil {
namespace {}  // namespace

LiveTotals run_live(Job& job, wire::Packetizer& packetizer, output::PacketOutput& out,
                    std::size_t pulses_per_window, navio::NavInput& nav,
                    const navpose::PoseBuffer& poses, const LiveOptions& opt,
                    const std::atomic<bool>& stop, std::uint64_t& packets_seen,
                    std::uint64_t& bytes_seen, std::int64_t& first_send_ns) {
    LiveTotals tot;
    const core::GpsTime start = job.options.start;
    const auto& scan = *job.sensor.scan;
    render::WindowRenderer wr(job.setup());
    std::vector<core::PointRecord> pts;
    render::RenderStats rstats;
    const std::int64_t t_begin = hostclock::monotonic_ns();
    std::int64_t next_status = t_begin + 1'000'000'000;
    std::uint64_t packets_at_status = 0, bytes_at_status = 0, nav_at_status = 0;
    bool stale = false;
    std::string stale_reason;
    std::deque<std::int64_t> pending;  // arrivals not yet answered by a packet
    sensor::PulseSpec spec_first{}, spec_last{};

    for (std::uint64_t k = 0; !stop.load(); k += pulses_per_window) {
        scan.pulses(k, 1, &spec_first);
        scan.pulses(k + pulses_per_window - 1, 1, &spec_last);
        const core::GpsTime t_first = start + core::Nanos(spec_first.t_ns);
        const core::GpsTime t_last = start + core::Nanos(spec_last.t_ns);
        if (opt.duration.count() > 0 && t_first - start >= opt.duration) break;
        const std::int64_t off = nav.offset_ns().value_or(0);
        hostclock::sleep_until_monotonic(t_last.time_since_epoch().count() + off);

        for (std::int64_t a : nav.take_arrivals()) pending.push_back(a);
        pts.clear();
        ++tot.windows;
        const auto traj = poses.window(t_first, t_last, (t_last - t_first) / 2);
        if (traj) {
            wr.render(*traj, k, pulses_per_window, pts, rstats);
            if (stale) stale = false;
        } else {
            ++tot.stale_windows;
            if (!stale) {
                ++tot.stale_periods;
                stale = true;
            }
            const auto q = poses.at(t_last);
            stale_reason =
                q.status == navpose::PoseStatus::Empty
                    ? "no navigation yet"
                    : fmt::format("no navigation for {:.0f} ms", double(q.age.count()) / 1e6);
        }
        tot.points += pts.size();
        first_send_ns = 0;
        packetizer.add(pts);
        packetizer.advance_to(k + pulses_per_window);
        if (first_send_ns != 0) {
            for (std::int64_t a : pending)
                tot.latency.add(core::Nanos(std::max<std::int64_t>(0, first_send_ns - a)));
            pending.clear();
        }

        const std::int64_t now = hostclock::monotonic_ns();
        if (opt.status_line && now >= next_status) {
            const auto nc = nav.counters();
            const auto newest = poses.newest();
            const double age_ms = newest ? double((t_last - *newest).count()) / 1e6 : 0.0;
            std::fprintf(stderr,
                         "\rlive: nav %llu msg/s, rejected %llu, pose age %.1f ms, stale %llu "
                         "periods%s%s | %llu pkt/s %.2f Mbit/s | INS->packet p99 %.2f ms   ",
                         static_cast<unsigned long long>(nc.applied - nav_at_status),
                         static_cast<unsigned long long>(nc.decode_rejected + nc.pose_rejected),
                         age_ms, static_cast<unsigned long long>(tot.stale_periods),
                         stale ? " — STALE: " : "", stale ? stale_reason.c_str() : "",
                         static_cast<unsigned long long>(packets_seen - packets_at_status),
                         double(bytes_seen - bytes_at_status) * 8e-6,
                         double(tot.latency.percentile(0.99).count()) / 1e6);
            std::fflush(stderr);
            nav_at_status = nc.applied;
            packets_at_status = packets_seen;
            bytes_at_status = bytes_seen;
            next_status += 1'000'000'000;
            if (next_status < now) next_status = now + 1'000'000'000;
        }
    }
    if (opt.status_line) std::fprintf(stderr, "\n");
    tot.packets = packets_seen;
    tot.bytes = bytes_seen;
    tot.seconds = double(hostclock::monotonic_ns() - t_begin) / 1e9;
    (void)out;
    return tot;
}

}  // namespace mirage::hil
