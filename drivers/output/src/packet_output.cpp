// SPDX-License-Identifier: Apache-2.0
#include "mirage/output/packet_output.hpp"

#include <fmt/format.h>

#include <cstdio>

#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/udp/pacing_probe.hpp"

namespace mirage::output {

udp::StreamPorts sensor_ports(bool ouster, std::uint16_t data, std::uint16_t position,
                              std::uint16_t imu) {
    udp::StreamPorts ports;
    ports.data = data ? data : (ouster ? 7502 : 2368);
    ports.position = ouster ? 0 : position;
    ports.imu = ouster ? imu : 0;
    return ports;
}

void route_streams(PacketOutputOptions& po, const udp::StreamPorts& ports, const std::string& host,
                   std::uint16_t source_port) {
    po.pcap_source_ports = {ports.data, ports.position, ports.imu};
    po.pcap_dest_ports = ports;
    if (host.empty()) return;
    udp::SenderConfig sc;
    sc.host = host;
    sc.ports = ports;
    sc.source_ports.data = source_port;
    po.udp = sc;
}
namespace {

udp::PacerConfig pacer_config(const PacketOutputOptions& o) {
    udp::PacerConfig c;
    c.as_fast_as_possible = !o.realtime;
    return c;
}

}  // namespace

PacketOutput::PacketOutput(PacketOutputOptions options)
    : opt_(std::move(options)), pacer_(pacer_config(opt_)) {
    if (opt_.udp) {
        sender_ = std::make_unique<udp::UdpSender>(*opt_.udp);
        pcap_dst_.ip = sender_->destination();
        pcap_dst_ports_ = opt_.udp->ports;
    } else {
        pcap_dst_.ip = {255, 255, 255, 255};  // what a factory-configured sensor sends to
        pcap_dst_ports_ = opt_.pcap_dest_ports;
    }
    if (!opt_.pcap_path.empty()) pcap_ = std::make_unique<pcap::Writer>(opt_.pcap_path, true);
    if (sender_ && opt_.realtime && opt_.shared_sender) start_shared();
}

void PacketOutput::start_shared() {
    const auto& ss = opt_.shared_sender;
    const auto id = ss->open(*sender_);
    shared_ = std::make_unique<SharedChannel>(ss, id);
    // The sending thread is the one that needs FIFO: report its state as the output's (its
    // owner reports a refusal).
    totals_.fifo = ss->fifo();
    totals_.fifo_error = ss->fifo_error();
}

void PacketOutput::operator()(const wire::PacketView& packet) {
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
        started_ = true;
        first_ = last_status_ = last_tick_ = now;
        // With a shared sender only its thread runs FIFO: a FIFO writer would take its encoding
        // bursts from the render workers, which need the CPU more (issue 3 item 9).
        if (opt_.realtime && opt_.fifo_priority > 0 && !shared_) {
            if (udp::set_realtime_priority(opt_.fifo_priority, totals_.fifo_error)) {
                totals_.fifo = true;
            } else {
                std::fprintf(stderr,
                             "packet output: SCHED_FIFO %d not set (%s); pacing without it\n",
                             opt_.fifo_priority, totals_.fifo_error.c_str());
            }
        }
        // --keep-awake: this thread paces, on the CPU kept out of idle (docs/time.md §5).
        if (opt_.realtime && opt_.pin_cpu >= 0 && !shared_) {
            std::string why;
            if (!hostclock::pin_current_thread(opt_.pin_cpu, why))
                std::fprintf(stderr, "packet output: not pinned to %s; pacing unpinned\n",
                             why.c_str());
        }
    }
    if (opt_.realtime && !pacer_.anchored())
        pacer_.anchor(packet.time, hostclock::monotonic_ns() + opt_.start_lead.count());
    std::int64_t step = 0;  // the capture host's clock steps with the device's
    if (opt_.clock_follower) {
        step = opt_.clock_follower->step().load(std::memory_order_relaxed);
        opt_.clock_follower->poll(hostclock::monotonic_ns());
    }
    if (shared_) {
        // The sending thread paces; this thread only waits while it is a horizon ahead.
        shared_->sender->submit(shared_->id, packet.stream, pacer_.deadline_ns(packet.time),
                                packet.bytes);
    } else if (opt_.realtime) {
        pacer_.wait(packet.time);
    }
    if (sender_ && !shared_) {
        if (sender_->send(packet))
            ++totals_.sent;
        else
            ++totals_.send_failed;
    }
    if (pcap_) {
        pcap::Endpoint src = opt_.pcap_source, dst = pcap_dst_;
        src.port = opt_.pcap_source_ports.port(packet.stream);
        dst.port = pcap_dst_ports_.port(packet.stream);
        if (pcap_->write(core::unix_ns_from_gps(packet.time) + step, src, dst, packet.bytes))
            ++totals_.pcap_packets;
    }
    ++totals_.packets;
    totals_.bytes += packet.bytes.size();
    if (now - last_tick_ >= std::chrono::seconds(1)) tick(now);
}

// Once a second: push the capture to disk, so a full disk is reported while streaming (the
// stream goes on without the capture) rather than at the end, and refresh the status line.
void PacketOutput::tick(std::chrono::steady_clock::time_point now) {
    last_tick_ = now;
    if (pcap_) {
        try {
            pcap_->flush();
        } catch (const IoError& e) {
            pcap_error_ = e.what();
            pcap_.reset();  // closing again reports the same error; the file keeps whole records
            std::fprintf(stderr, "\n%s; capture stopped, stream continues\n", pcap_error_.c_str());
        }
    }
    if (opt_.status_line) print_status(false);
}

void PacketOutput::print_status(bool final) {
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::chrono::duration<double>(now - last_status_).count();
    const double rate = dt > 0 ? double(totals_.packets - packets_at_status_) / dt : 0.0;
    const double mbit = dt > 0 ? 8e-6 * double(totals_.bytes - bytes_at_status_) / dt : 0.0;
    std::uint64_t late = 0, failed = totals_.send_failed;
    double worst_us = 0;
    if (shared_) {
        const auto c = shared_->sender->counters(shared_->id);
        late = c.late;
        failed = c.failed;
        worst_us = double(c.worst.count()) / 1e3;
    } else {
        late = pacer_.stats().late();
        worst_us = double(pacer_.stats().worst().count()) / 1e3;
    }
    std::fprintf(stderr,
                 "\r%8.1f s  %7.0f packets/s  %7.2f Mbit/s  late %llu  worst %.0f µs  failed "
                 "sends %llu   %s",
                 std::chrono::duration<double>(now - first_).count(), rate, mbit,
                 static_cast<unsigned long long>(late), worst_us,
                 static_cast<unsigned long long>(failed), final ? "\n" : "");
    std::fflush(stderr);
    status_printed_ = true;
    last_status_ = now;
    packets_at_status_ = totals_.packets;
    bytes_at_status_ = totals_.bytes;
}

std::string late_share_text(const PacketOutputTotals& t) {
    if (t.paced == 0) return {};
    return fmt::format("50 µs late or more {:.3f} % of {}",
                       100.0 * double(t.from_50us) / double(t.paced), t.paced);
}

PacketOutputTotals PacketOutput::finish() {
    udp::LatenessHistogram shared_stats;
    if (shared_) {
        shared_->sender->flush(shared_->id);  // every packet of this output is on the wire
        const auto c = shared_->sender->counters(shared_->id);
        totals_.sent = c.sent;
        totals_.send_failed = c.failed;
        totals_.discarded = c.discarded;
        shared_stats = shared_->sender->lateness(shared_->id);
        const udp::LatenessHistogram send = shared_->sender->send_durations(shared_->id);
        totals_.send_p50 = send.percentile(0.50);
        totals_.send_p99 = send.percentile(0.99);
    }
    if (opt_.status_line && started_) {
        if (std::chrono::steady_clock::now() - last_status_ > std::chrono::milliseconds(300))
            print_status(true);
        else if (status_printed_)
            std::fputc('\n', stderr);  // end the status line printed just now
    }
    if (pcap_) pcap_->close();
    if (!pcap_error_.empty()) throw IoError(pcap_error_);
    const auto& st = shared_ ? shared_stats : pacer_.stats();
    totals_.late = st.late();
    totals_.paced = opt_.realtime ? st.count() : 0;  // as fast as possible: nothing was paced
    totals_.from_50us = st.count_from(std::chrono::microseconds(50));
    totals_.worst_late = st.worst();
    totals_.p50 = st.percentile(0.50);
    totals_.p99 = st.percentile(0.99);
    totals_.seconds =
        started_ ? std::chrono::duration<double>(std::chrono::steady_clock::now() - first_).count()
                 : 0.0;
    return totals_;
}

}  // namespace mirage::output
