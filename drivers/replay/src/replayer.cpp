// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/replayer.hpp"

#include <fmt/format.h>
#include <pcap/pcap.h>
#include <time.h>

#include <cmath>
#include <deque>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/replay/batch_sender.hpp"
#include "mirage/udp/pacer.hpp"

namespace mirage::replay {
namespace {

using udp::Pacer;

class Scheduler {
  public:
    Scheduler(const ReplayConfig& c, ReplaySummary& s, BatchSender& sender,
              const std::atomic<bool>* stop,
              const std::function<void(const ReplaySummary&)>& progress)
        : c_(c), s_(s), sender_(sender), stop_(stop), progress_(progress), top_(c.speed <= 0.0) {}

    // At top speed, datagrams handed to the sender at once: enough for several full GSO runs
    // per system call.
    static constexpr std::size_t kTopBatch = 1024;
    std::size_t lookahead() const { return top_ ? 2 * kTopBatch : 64; }

    void add(Packet&& p) { queue_.push_back(std::move(p)); }

    // Sends from the queue until it is shorter than `keep` (0: empty). False when stopped.
    bool drain(std::size_t keep) {
        while (queue_.size() > keep) {
            if (stop_ && stop_->load(std::memory_order_relaxed)) return false;
            if (!send_next()) return false;
        }
        return true;
    }

  private:
    std::int64_t deadline(std::int64_t t) const {
        if (c_.speed == 1.0) return anchor_ + t;
        return anchor_ + static_cast<std::int64_t>(std::llround(static_cast<double>(t) / c_.speed));
    }

    bool send_next() {
        std::size_t n = 0;
        std::int64_t send_time = 0;
        if (anchor_ < 0) {
            anchor_ = hostclock::monotonic_ns() + c_.lead_ns - queue_.front().time_ns;
            s_.anchor_ns = anchor_ + queue_.front().time_ns;
        }
        if (top_) {
            n = std::min(queue_.size(), kTopBatch);
            send_time = hostclock::monotonic_ns();
        } else {
            const std::int64_t first = deadline(queue_.front().time_ns);
            if (!hostclock::wait_until_monotonic(first, c_.spin_ns, stop_)) return false;
            send_time = hostclock::monotonic_ns();
            // Everything already due goes in the same system call.
            n = 1;
            while (n < queue_.size() && n < BatchSender::kMaxBatch &&
                   deadline(queue_[n].time_ns) <= send_time)
                ++n;
        }
        batch_.clear();
        for (std::size_t i = 0; i < n; ++i) {
            const auto& p = queue_[i];
            batch_.push_back({p.payload, p.dst_port});
            if (!top_) {
                const std::int64_t d = deadline(p.time_ns);
                s_.lateness.add(core::Nanos{send_time - d});
                if (first_deadline_ < 0) first_deadline_ = d;
                s_.schedule_ns = d - first_deadline_;
            }
        }
        const std::size_t ok = sender_.send(batch_);
        const std::int64_t sent = hostclock::monotonic_ns();
        std::size_t bytes = 0;
        for (const auto& o : batch_) bytes += o.payload.size();
        s_.packets += ok;
        if (ok == n)
            s_.bytes += bytes;  // else per-message attribution is unknown: approximate
        else
            s_.bytes += bytes * ok / std::max<std::size_t>(n, 1);
        s_.failed = sender_.failed();
        s_.syscalls = sender_.syscalls();
        s_.gso_messages = sender_.gso_messages();
        if (first_send_ < 0) first_send_ = send_time;
        s_.elapsed_ns = sent - first_send_;
        if (top_) s_.schedule_ns = s_.elapsed_ns;
        queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(n));
        if (progress_ && send_time - last_progress_ >= 1'000'000'000) {
            last_progress_ = send_time;
            progress_(s_);
        }
        return true;
    }

    const ReplayConfig& c_;
    ReplaySummary& s_;
    BatchSender& sender_;
    const std::atomic<bool>* stop_;
    const std::function<void(const ReplaySummary&)>& progress_;
    bool top_;
    std::deque<Packet> queue_;
    std::vector<Outgoing> batch_;
    std::int64_t anchor_ = -1, first_deadline_ = -1, first_send_ = -1, last_progress_ = 0;
};

}  // namespace

ReplaySummary replay(const ReplayConfig& c, const std::atomic<bool>* stop,
                     const std::function<void(const ReplaySummary&)>& on_progress) {
    if (!(c.speed >= 0.0) || !std::isfinite(c.speed))
        throw ConfigError(fmt::format("replay --speed {}: expected >= 0 (0: top speed)", c.speed));
    if (c.until_ns >= 0 && c.until_ns <= c.from_ns)
        throw ConfigError("replay --until: must be later than --from");
    ReplaySummary s;
    s.top_speed = c.speed <= 0.0;
    Impairer impairer(c.impair);
    BatchSender sender(c.host, c.send_buffer_bytes);
    Scheduler sched(c, s, sender, stop, on_progress);
    std::vector<Packet> ready;
    std::int64_t pass_offset = 0;
    bool stopped = false;
    for (std::uint32_t pass = 0; (c.loops == 0 || pass < c.loops) && !stopped; ++pass) {
        pcap::Reader reader(c.path, pcap::ReaderOptions{.unknown_link_throws = false});
        if (!c.filter.empty()) reader.set_filter(c.filter);
        s.link_type = reader.link_type();
        s.link_supported = reader.link_supported();
        pcap::UdpDatagram d;
        std::int64_t first = -1, last_rel = -1;
        std::uint64_t used = 0;
        while (reader.next(d)) {
            ++s.datagrams_read;
            if (first < 0) first = d.time_ns;
            const std::int64_t rel = d.time_ns - first;
            if (c.until_ns >= 0 && rel >= c.until_ns) {
                ++s.out_of_range;
                break;  // the rest of the file is later still (captures are in time order)
            }
            // A datagram stamped before the first (a capture slightly out of time order) is due
            // at once, not dropped, unless --from asks for a later start.
            if (c.from_ns > 0 && rel < c.from_ns) {
                ++s.out_of_range;
                continue;
            }
            const auto it = c.port_map.find(d.dst.port);
            Packet p{pass_offset + rel - c.from_ns,
                     it == c.port_map.end() ? d.dst.port : it->second, std::move(d.payload)};
            last_rel = std::max(last_rel, rel - c.from_ns);
            ++used;
            ready.clear();
            impairer.push(std::move(p), ready);
            for (auto& r : ready) sched.add(std::move(r));
            if (!sched.drain(sched.lookahead())) {
                stopped = true;
                break;
            }
        }
        for (std::size_t i = 0; i < pcap::kFrameStatusCount; ++i) s.frames[i] += reader.counts()[i];
        s.filtered += reader.filtered();
        ++s.passes;
        if (!reader.error().empty()) {
            s.error = fmt::format("'{}': {}", c.path, reader.error());
            s.error_offset = reader.error_offset();
            break;  // a damaged file is not looped over
        }
        if (used == 0) break;
        // The next pass starts one mean packet interval after this one's last datagram.
        const std::int64_t gap =
            used > 1 ? last_rel / static_cast<std::int64_t>(used - 1) : 1'000'000;
        pass_offset += last_rel + std::max<std::int64_t>(gap, 1);
    }
    ready.clear();
    impairer.finish(ready);
    for (auto& r : ready) sched.add(std::move(r));
    if (!stopped && !sched.drain(0)) stopped = true;
    s.stopped = stopped;
    s.impair = impairer.counters();
    return s;
}

std::string format_summary(const ReplaySummary& s) {
    std::string out;
    const double secs = static_cast<double>(s.elapsed_ns) * 1e-9;
    out += fmt::format(
        "replay: {} packets, {} payload bytes sent in {:.6f} s (first send call to "
        "the end of the last)",
        s.packets, s.bytes, secs);
    if (!s.top_speed)
        out += fmt::format(" (schedule {:.6f} s)", static_cast<double>(s.schedule_ns) * 1e-9);
    out += fmt::format(", {} pass{}{}\n", s.passes, s.passes == 1 ? "" : "es",
                       s.stopped ? ", stopped early" : "");
    out += "  skipped frames:";
    for (std::size_t i = 1; i < pcap::kFrameStatusCount; ++i)
        out += fmt::format(" {} {}{}", pcap::to_string(static_cast<pcap::FrameStatus>(i)),
                           s.frames[i], i + 1 < pcap::kFrameStatusCount ? "," : "");
    out += fmt::format("; filtered {}; outside --from/--until {}; send failures {}\n", s.filtered,
                       s.out_of_range, s.failed);
    if (!s.link_supported) {
        const char* name = pcap_datalink_val_to_name(s.link_type);
        out += fmt::format("  link type {} ({}) not supported: all its frames skipped\n",
                           s.link_type, name ? name : "unknown");
    }
    if (s.impair.in != s.impair.out || s.impair.reordered || s.impair.duplicated)
        out += fmt::format("  impairments: dropped {} ({} bursts), duplicated {}, reordered {}\n",
                           s.impair.dropped, s.impair.drop_events, s.impair.duplicated,
                           s.impair.reordered);
    if (s.top_speed) {
        const double pps = secs > 0 ? static_cast<double>(s.packets) / secs : 0.0;
        out += fmt::format(
            "  top speed: {:.0f} packets/s, {:.1f} packets per sendmmsg, {} UDP GSO messages\n",
            pps,
            s.syscalls ? static_cast<double>(s.packets + s.failed) / static_cast<double>(s.syscalls)
                       : 0.0,
            s.gso_messages);
    } else {
        const auto us = [](core::Nanos n) { return static_cast<double>(n.count()) * 1e-3; };
        out += fmt::format(
            "  timing error (send call - schedule): p50 {:.0f} us, p99 {:.0f} us, max {:.1f} us "
            "over {} packets\n",
            us(s.lateness.percentile(0.5)), us(s.lateness.percentile(0.99)), us(s.lateness.worst()),
            s.lateness.count());
    }
    if (!s.error.empty())
        out += fmt::format("  ERROR: read stopped at byte {}: {}\n", s.error_offset, s.error);
    return out;
}

}  // namespace mirage::replay
