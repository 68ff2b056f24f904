// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/pacing_probe.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cstring>
#include <thread>
#include <vector>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/udp/udp_sender.hpp"

namespace mirage::udp {
namespace {

std::int64_t minimum(const std::vector<std::int64_t>& v) {
    return v.empty() ? 0 : *std::min_element(v.begin(), v.end());
}

double us(core::Nanos d) { return static_cast<double>(d.count()) / 1e3; }

}  // namespace

bool set_realtime_priority(int priority, std::string& why) {
    sched_param p{};
    p.sched_priority = priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    if (rc != 0) why = std::strerror(rc);
    return rc == 0;
}

PacingProbeReport run_pacing_probe(const PacingProbeConfig& config) {
    PacingProbeReport report;
    report.wire = LatenessHistogram(config.late_threshold);
    report.pacer = LatenessHistogram(config.late_threshold);
    report.scheduled = config.packets;
    if (config.packets == 0 || config.rate_hz == 0) return report;

    UdpReceiver receiver;
    SenderConfig sc;
    sc.host = "127.0.0.1";
    sc.ports = StreamPorts{receiver.port(), 0, 0};
    UdpSender sender(sc);

    std::vector<std::int64_t> rx_ns(config.packets, 0);  // kernel time per sequence number
    std::vector<std::int64_t> deadline_ns(config.packets, 0);
    const auto period = [&](std::uint64_t k) {
        return core::Nanos{static_cast<std::int64_t>(k * 1'000'000'000ull / config.rate_hz)};
    };
    const auto last_deadline_slack = period(config.packets) + std::chrono::seconds(1);

    std::thread rx([&] {
        ReceivedDatagram d;
        std::uint64_t got = 0;
        while (got < config.packets && receiver.receive(d, last_deadline_slack)) {
            std::uint64_t seq = 0;
            if (d.payload.size() < sizeof seq) continue;
            std::memcpy(&seq, d.payload.data(), sizeof seq);
            if (seq < config.packets && rx_ns[seq] == 0) {
                rx_ns[seq] = d.kernel_time_ns;
                ++got;
            }
        }
    });

    int old_policy = 0;
    sched_param old_param{};
    pthread_getschedparam(pthread_self(), &old_policy, &old_param);
    if (config.fifo_priority > 0) {
        std::string why;
        if (!set_realtime_priority(config.fifo_priority, why))
            fmt::print(stderr, "pacing probe: SCHED_FIFO {} not set: {}\n", config.fifo_priority,
                       why);
    }
    const std::int64_t offset = hostclock::realtime_minus_monotonic();
    Pacer pacer(PacerConfig{false, core::Nanos{50'000}, config.late_threshold});
    const core::GpsTime t0{};
    // Start 10 ms ahead so the first packets are not late because of thread start-up.
    pacer.anchor(t0, hostclock::monotonic_ns() + 10'000'000);
    std::vector<std::uint8_t> payload(std::max<std::size_t>(config.payload_bytes, 8), 0);
    for (std::uint64_t k = 0; k < config.packets; ++k) {
        const core::GpsTime t = t0 + period(k);
        std::memcpy(payload.data(), &k, sizeof k);
        pacer.wait(t);
        sender.send(wire::Stream::Data, payload);
        deadline_ns[k] = pacer.deadline_ns(t);
    }
    pthread_setschedparam(pthread_self(), old_policy, &old_param);
    rx.join();
    report.pacer = pacer.stats();
    report.failed_sends = sender.total().failed;

    const std::uint64_t tenth = std::max<std::uint64_t>(1, config.packets / 10);
    std::vector<std::int64_t> head, tail;
    for (std::uint64_t k = 0; k < config.packets; ++k) {
        if (rx_ns[k] == 0) continue;
        ++report.received;
        const std::int64_t late = rx_ns[k] - offset - deadline_ns[k];
        report.wire.add(core::Nanos{late});
        if (k < tenth) head.push_back(late);
        if (k >= config.packets - tenth) tail.push_back(late);
    }
    report.drift = core::Nanos{minimum(tail) - minimum(head)};
    report.schedule_span = core::Nanos{deadline_ns.back() - deadline_ns.front()};
    if (rx_ns.front() != 0 && rx_ns.back() != 0)
        report.received_span = core::Nanos{rx_ns.back() - rx_ns.front()};
    return report;
}

std::string format_report(const PacingProbeReport& r) {
    return fmt::format(
        "packets {}/{} received ({} failed sends); span {:.3f} ms (schedule {:.3f} ms), "
        "drift {:.1f} us; "
        "lateness vs schedule from kernel timestamps: p50 {:.0f} us, p99 {:.0f} us, max {:.1f} us, "
        "{} over {:.0f} us; pacer wake-up: p50 {:.0f} us, p99 {:.0f} us, max {:.1f} us",
        r.received, r.scheduled, r.failed_sends, us(r.received_span) / 1e3,
        us(r.schedule_span) / 1e3, us(r.drift), us(r.wire.percentile(0.5)),
        us(r.wire.percentile(0.99)), us(r.wire.worst()), r.wire.late(), us(r.wire.threshold()),
        us(r.pacer.percentile(0.5)), us(r.pacer.percentile(0.99)), us(r.pacer.worst()));
}

}  // namespace mirage::udp
