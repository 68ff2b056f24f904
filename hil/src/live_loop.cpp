// SPDX-License-Identifier: Apache-2.0
#include "live_loop.hpp"

#include <fmt/format.h>

#include <cstdio>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/render/pipeline.hpp"

namespace mirage::hil {
namespace {

std::size_t track_index(navpose::Track t) { return t == navpose::Track::Position ? 0 : 1; }

}  // namespace

LiveSession::LiveSession(Job& job, output::PacketOutput& out, navio::NavInput& nav,
                         const navpose::PoseBuffer& poses, LiveOptions options)
    : job_(job), out_(out), nav_(nav), poses_(poses), opt_(options) {}

void LiveSession::on_packet(const wire::PacketView& p) {
    out_(p);
    ++tot_.packets;
    tot_.bytes += p.bytes.size();
    if (p.stream != wire::Stream::Data || rendered_.empty()) return;
    const std::int64_t sent = hostclock::monotonic_ns();
    for (const std::uint64_t seq : rendered_) {
        const auto it = pending_.find(seq);
        tot_.latency.add(core::Nanos(std::max<std::int64_t>(0, sent - it->second.arrival_ns)));
        pending_.erase(it);
    }
    rendered_.clear();
}

void LiveSession::take_messages() {
    for (const navio::AppliedMessage& m : nav_.take_applied()) {
        if (!timing_) continue;
        pending_[m.tag.seq] = {m.tag.arrival_ns, m.position, m.attitude, false};
        ++tot_.messages;
    }
}

// Messages not yet in a packet become due with the next data packet.
void LiveSession::note_used(const std::vector<navpose::UsedMessage>& used) {
    for (const navpose::UsedMessage& u : used) {
        const std::size_t k = track_index(u.track);
        if (!any_used_[k] || u.tag.seq > newest_used_[k]) newest_used_[k] = u.tag.seq;
        any_used_[k] = true;
        const auto it = pending_.find(u.tag.seq);
        if (it == pending_.end() || it->second.rendered) continue;  // backlog, or already due
        it->second.rendered = true;
        rendered_.push_back(u.tag.seq);
    }
}

// What never reached a packet: superseded when every track it updated had a newer sample used
// before it (a window always uses the newest samples up to its time).
void LiveSession::count_unused() {
    for (const auto& [seq, m] : pending_) {
        const bool pos_newer = !m.position || (any_used_[0] && newest_used_[0] > seq);
        const bool att_newer = !m.attitude || (any_used_[1] && newest_used_[1] > seq);
        if (!m.rendered && pos_newer && att_newer)
            ++tot_.superseded;
        else
            ++tot_.unused_at_end;
    }
}

LiveTotals LiveSession::run(wire::Packetizer& packetizer, std::size_t pulses_per_window,
                            const std::atomic<bool>& stop) {
    const core::GpsTime start = job_.options.start;
    const auto& scan = *job_.sensor.scan;
    render::WindowRenderer wr(*job_.scene, *job_.renderer, job_.sensor, job_.mount, job_.env,
                              job_.options);
    std::vector<core::PointRecord> pts;
    render::RenderStats rstats;
    const std::int64_t t_begin = hostclock::monotonic_ns();
    next_status_ns_ = t_begin + 1'000'000'000;
    bool stale = false;
    std::string stale_reason;
    sensor::PulseSpec spec_first{}, spec_last{};
    take_messages();  // the backlog before pulse 0 is not latency
    timing_ = true;

    for (std::uint64_t k = 0; !stop.load(); k += pulses_per_window) {
        scan.pulses(k, 1, &spec_first);
        scan.pulses(k + pulses_per_window - 1, 1, &spec_last);
        const core::GpsTime t_first = start + core::Nanos(spec_first.t_ns);
        const core::GpsTime t_last = start + core::Nanos(spec_last.t_ns);
        if (opt_.duration.count() > 0 && t_first - start >= opt_.duration) break;
        const std::int64_t off = nav_.offset_ns().value_or(0);
        hostclock::sleep_until_monotonic(t_last.time_since_epoch().count() + off);

        pts.clear();
        ++tot_.windows;
        const auto win = poses_.window(t_first, t_last, (t_last - t_first) / 2);
        // After the window: every message it used has been listed by then (NavInput lists a
        // message before its samples reach the pose buffer).
        take_messages();
        if (win) {
            wr.render(win->trajectory, k, pulses_per_window, pts, rstats);
            note_used(win->used);
            stale = false;
        } else {
            ++tot_.stale_windows;
            if (!stale) ++tot_.stale_periods;
            stale = true;
            const auto q = poses_.at(t_last);
            stale_reason =
                q.status == navpose::PoseStatus::Empty
                    ? "no navigation yet"
                    : fmt::format("no navigation for {:.0f} ms", double(q.age.count()) / 1e6);
        }
        tot_.points += pts.size();
        packetizer.add(pts);
        packetizer.advance_to(k + pulses_per_window);
        if (opt_.status_line) print_status(t_last, stale, stale_reason);
    }
    if (opt_.status_line) std::fprintf(stderr, "\n");
    take_messages();
    count_unused();
    tot_.seconds = double(hostclock::monotonic_ns() - t_begin) / 1e9;
    return tot_;
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
                 double(tot_.latency.percentile(0.99).count()) / 1e6);
    std::fflush(stderr);
    nav_at_status_ = nc.track.applied;
    packets_at_status_ = tot_.packets;
    bytes_at_status_ = tot_.bytes;
    next_status_ns_ += 1'000'000'000;
    if (next_status_ns_ < now) next_status_ns_ = now + 1'000'000'000;
}

}  // namespace mirage::hil
