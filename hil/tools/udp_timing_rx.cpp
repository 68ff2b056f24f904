// SPDX-License-Identifier: Apache-2.0
// mirage-udp-timing-rx: the receiving end of scripts/bench-replay (issue 5, item 6). It knows the
// schedule from the capture being replayed, receives the replayed UDP datagrams with kernel
// receive timestamps (SO_TIMESTAMPNS), matches each to its capture packet by port and payload
// hash, and reports the timing error rx − (anchor + capture offset), anchored on the first
// matched packet, plus drift, loss and the receive rate. A second mode writes a long capture by
// repeating a short one (the 10-minute no-drift run), so the schedule needs no loop semantics.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/udp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/pcap/writer.hpp"
#include "mirage/udp/pacer.hpp"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

// 64-bit word-wise hash of a payload: fast enough for a million packets per second, and replayed
// lidar packets carry their own timestamps, so distinct packets have distinct payloads.
std::uint64_t payload_hash(const std::uint8_t* p, std::size_t n) {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL ^ n;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001b3ULL;
        h ^= h >> 29;
    }
    for (; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
    return h ^ (h >> 32);
}

struct Scheduled {
    std::int64_t offset_ns;  // capture time − the first datagram's
    std::uint64_t hash;
    std::uint16_t port;
};

struct Received {
    std::int64_t rx_ns;  // kernel CLOCK_REALTIME receive time
    std::uint64_t hash;
    std::uint16_t port;
};

std::vector<Scheduled> load_schedule(const std::string& path, const std::set<std::uint16_t>& ports,
                                     std::set<std::uint16_t>& seen_ports) {
    mirage::pcap::Reader reader(path);
    mirage::pcap::UdpDatagram d;
    std::vector<Scheduled> out;
    std::int64_t t0 = 0;
    while (reader.next(d)) {
        if (!ports.empty() && !ports.count(d.dst.port)) continue;
        if (out.empty()) t0 = d.time_ns;
        seen_ports.insert(d.dst.port);
        out.push_back(
            {d.time_ns - t0, payload_hash(d.payload.data(), d.payload.size()), d.dst.port});
    }
    return out;
}

// Repeats `in` `copies` times, each copy shifted by period = span + mean gap, so the long capture
// keeps the short one's packet rate across the seams.
int make_long(const std::string& in, const std::string& out, double seconds) {
    const auto dgrams = mirage::pcap::read_udp(in);
    if (dgrams.size() < 2) {
        std::fprintf(stderr, "udp-timing-rx: '%s': needs at least 2 UDP datagrams\n", in.c_str());
        return 1;
    }
    const std::int64_t span = dgrams.back().time_ns - dgrams.front().time_ns;
    const std::int64_t period = span + span / static_cast<std::int64_t>(dgrams.size() - 1);
    const auto copies = static_cast<std::int64_t>(seconds * 1e9 / static_cast<double>(period)) + 1;
    mirage::pcap::Writer writer(out, true);
    for (std::int64_t k = 0; k < copies; ++k)
        for (const auto& d : dgrams) writer.write(d.time_ns + k * period, d.src, d.dst, d.payload);
    writer.close();
    std::printf("udp-timing-rx: wrote %s: %lld copies, %llu datagrams, period %.6f s\n",
                out.c_str(), static_cast<long long>(copies),
                static_cast<unsigned long long>(writer.datagrams()),
                static_cast<double>(period) * 1e-9);
    return 0;
}

int open_socket(const std::string& bind_addr, std::uint16_t port, int rcvbuf, bool gro) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
    // UDP GRO (Linux ≥ 5.0): a run of datagrams a sender passed as one GSO buffer stays one
    // buffer up to this socket, instead of the kernel cutting it into datagrams on the way in;
    // receive() cuts it by the segment size. At top speed that per-datagram kernel work, done on
    // the sender's core over veth, otherwise caps the rate the receiver can take.
    if (gro) ::setsockopt(fd, SOL_UDP, UDP_GRO, &one, sizeof one);
    // As root, beyond net.core.rmem_max: a top-speed burst must not overflow the queue.
    if (::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(port);
    if (::inet_pton(AF_INET, bind_addr.c_str(), &sa.sin_addr) != 1 ||
        ::bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

struct RxOptions {
    std::string bind = "0.0.0.0";
    double start_timeout_s = 30, idle_s = 1.0;
    int rcvbuf = 256 << 20;
    bool gro = true;
    std::string ready;
};

// Receives until every scheduled datagram arrived, `idle_s` passed without one after the first,
// nothing came within `start_timeout_s`, or a signal.
std::vector<Received> receive(const std::vector<int>& fds, const std::vector<std::uint16_t>& ports,
                              std::size_t expected, const RxOptions& o) {
    constexpr unsigned kBatch = 256;
    constexpr std::size_t kMaxPayload = 65536;
    std::vector<std::uint8_t> bufs(kBatch * kMaxPayload);
    std::vector<char> ctrl(kBatch * 64);
    std::vector<mmsghdr> msgs(kBatch);
    std::vector<iovec> iovs(kBatch);
    std::vector<Received> out;
    out.reserve(expected + expected / 8 + 16);
    std::vector<pollfd> pfds;
    for (int fd : fds) pfds.push_back({fd, POLLIN, 0});
    const std::int64_t start = mirage::hostclock::monotonic_ns();
    std::int64_t last_rx_mono = 0;
    while (!g_stop.load() && out.size() < expected) {
        const std::int64_t now = mirage::hostclock::monotonic_ns();
        if (out.empty() && now - start > static_cast<std::int64_t>(o.start_timeout_s * 1e9)) break;
        if (!out.empty() && now - last_rx_mono > static_cast<std::int64_t>(o.idle_s * 1e9)) break;
        if (::poll(pfds.data(), static_cast<nfds_t>(pfds.size()), 20) <= 0) continue;
        for (std::size_t s = 0; s < pfds.size(); ++s) {
            if (!(pfds[s].revents & POLLIN)) continue;
            for (;;) {
                for (unsigned i = 0; i < kBatch; ++i) {
                    iovs[i] = {bufs.data() + i * kMaxPayload, kMaxPayload};
                    msgs[i].msg_hdr = {};
                    msgs[i].msg_hdr.msg_iov = &iovs[i];
                    msgs[i].msg_hdr.msg_iovlen = 1;
                    msgs[i].msg_hdr.msg_control = ctrl.data() + i * 64;
                    msgs[i].msg_hdr.msg_controllen = 64;
                }
                const int n = ::recvmmsg(pfds[s].fd, msgs.data(), kBatch, MSG_DONTWAIT, nullptr);
                if (n <= 0) break;
                for (int i = 0; i < n; ++i) {
                    std::int64_t ts = 0;
                    std::size_t segment = 0;  // GRO segment size; 0: one datagram
                    auto& h = msgs[static_cast<std::size_t>(i)].msg_hdr;
                    for (cmsghdr* c = CMSG_FIRSTHDR(&h); c; c = CMSG_NXTHDR(&h, c)) {
                        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
                            timespec t;
                            std::memcpy(&t, CMSG_DATA(c), sizeof t);
                            ts = static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
                        } else if (c->cmsg_level == SOL_UDP && c->cmsg_type == UDP_GRO) {
                            int g = 0;
                            std::memcpy(&g, CMSG_DATA(c), sizeof g);
                            if (g > 0) segment = static_cast<std::size_t>(g);
                        }
                    }
                    const std::size_t len = msgs[static_cast<std::size_t>(i)].msg_len;
                    const auto* base = static_cast<const std::uint8_t*>(h.msg_iov->iov_base);
                    const std::size_t step = segment > 0 ? segment : len;
                    // Every datagram of a GRO buffer arrived with it: same kernel time.
                    std::size_t off = 0;
                    do {
                        const std::size_t m = std::min(step, len - off);
                        out.push_back({ts, payload_hash(base + off, m), ports[s]});
                        off += m;
                    } while (off < len);
                }
                last_rx_mono = mirage::hostclock::monotonic_ns();
                if (static_cast<unsigned>(n) < kBatch) break;
            }
        }
    }
    return out;
}

double quantile(const std::vector<std::int64_t>& sorted, double q) {
    if (sorted.empty()) return 0;
    const auto i = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5);
    return static_cast<double>(sorted[std::min(i, sorted.size() - 1)]);
}

struct Analysis {
    std::size_t scheduled = 0, received = 0, matched = 0, lost = 0, unmatched = 0;
    double p50_us = 0, p99_us = 0, max_us = 0, min_us = 0, abs_p99_us = 0, jitter_p99_us = 0;
    double drift_min_us = 0, drift_median_us = 0;
    // Lateness: error − the least error (the clock relation; delays only add to it), as the
    // floor targets read it (docs/benchmarks.md §4).
    double late_p99_us = 0, late_over_50us_pct = 0;
    double rx_span_s = 0, schedule_span_s = 0, rx_pps = 0;
};

// Matches received datagrams to the schedule in order: a datagram that is not the next expected
// one is looked for in a window ahead (the ones skipped are lost); not found: unmatched (a
// duplicate, a reordered one or a stranger).
// One matched datagram: its index in the schedule and its timing error (for --errors).
struct ErrorRow {
    std::size_t index;
    std::uint16_t port;
    std::int64_t offset_ns, error_ns;
};

Analysis analyse(const std::vector<Scheduled>& sched, const std::vector<Received>& rx,
                 std::vector<ErrorRow>* rows = nullptr) {
    constexpr std::size_t kWindow = 4096;
    Analysis a;
    a.scheduled = sched.size();
    a.received = rx.size();
    std::vector<std::int64_t> err;  // receive order
    std::size_t j = 0;
    bool anchored = false;
    std::int64_t anchor = 0, matched_first_off = 0, matched_last_off = 0;
    for (const auto& r : rx) {
        std::size_t k = j;
        const std::size_t end = std::min(sched.size(), j + kWindow);
        while (k < end && (sched[k].hash != r.hash || sched[k].port != r.port)) ++k;
        if (k == end) {
            ++a.unmatched;
            continue;
        }
        a.lost += k - j;
        j = k + 1;
        if (!anchored) {
            anchor = r.rx_ns - sched[k].offset_ns;
            matched_first_off = sched[k].offset_ns;
            anchored = true;
        }
        matched_last_off = sched[k].offset_ns;
        err.push_back(r.rx_ns - (anchor + sched[k].offset_ns));
        if (rows) rows->push_back({k, sched[k].port, sched[k].offset_ns, err.back()});
    }
    a.lost += sched.size() - j;
    a.matched = err.size();
    if (rx.size() >= 2) {
        a.rx_span_s = static_cast<double>(rx.back().rx_ns - rx.front().rx_ns) * 1e-9;
        if (a.rx_span_s > 0) a.rx_pps = static_cast<double>(rx.size() - 1) / a.rx_span_s;
    }
    a.schedule_span_s = static_cast<double>(matched_last_off - matched_first_off) * 1e-9;
    if (err.empty()) return a;
    // Drift: the last tenth against the first tenth, by least error (delays only ever add
    // error, so the least of many packets is the clock relation itself) and by median.
    const std::size_t tenth = std::max<std::size_t>(1, err.size() / 10);
    auto head = std::vector<std::int64_t>(err.begin(), err.begin() + static_cast<long>(tenth));
    auto tail = std::vector<std::int64_t>(err.end() - static_cast<long>(tenth), err.end());
    std::sort(head.begin(), head.end());
    std::sort(tail.begin(), tail.end());
    a.drift_min_us = static_cast<double>(tail.front() - head.front()) * 1e-3;
    a.drift_median_us = (quantile(tail, 0.5) - quantile(head, 0.5)) * 1e-3;
    std::vector<std::int64_t> s = err;
    std::sort(s.begin(), s.end());
    a.p50_us = quantile(s, 0.5) * 1e-3;
    a.p99_us = quantile(s, 0.99) * 1e-3;
    a.max_us = static_cast<double>(s.back()) * 1e-3;
    a.min_us = static_cast<double>(s.front()) * 1e-3;
    const auto med = static_cast<std::int64_t>(quantile(s, 0.5));
    std::vector<std::int64_t> absv, jit;
    for (auto e : err) {
        absv.push_back(e < 0 ? -e : e);
        jit.push_back(e - med < 0 ? med - e : e - med);
    }
    std::sort(absv.begin(), absv.end());
    std::sort(jit.begin(), jit.end());
    a.abs_p99_us = quantile(absv, 0.99) * 1e-3;
    a.jitter_p99_us = quantile(jit, 0.99) * 1e-3;
    a.late_p99_us = (quantile(s, 0.99) - static_cast<double>(s.front())) * 1e-3;
    const auto over =
        std::count_if(s.begin(), s.end(), [&](std::int64_t e) { return e - s.front() > 50'000; });
    a.late_over_50us_pct = 100.0 * static_cast<double>(over) / static_cast<double>(s.size());
    return a;
}

// NaN or Inf (an empty run) becomes null: never a number JSON cannot hold.
nlohmann::json finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

std::string to_json(const std::string& label, const Analysis& a) {
    const nlohmann::ordered_json j = {{"label", label},
                                      {"scheduled", a.scheduled},
                                      {"received", a.received},
                                      {"matched", a.matched},
                                      {"lost", a.lost},
                                      {"unmatched", a.unmatched},
                                      {"err_p50_us", finite(a.p50_us)},
                                      {"err_p99_us", finite(a.p99_us)},
                                      {"err_max_us", finite(a.max_us)},
                                      {"err_min_us", finite(a.min_us)},
                                      {"abs_err_p99_us", finite(a.abs_p99_us)},
                                      {"jitter_p99_us", finite(a.jitter_p99_us)},
                                      {"late_p99_us", finite(a.late_p99_us)},
                                      {"late_over_50us_pct", finite(a.late_over_50us_pct)},
                                      {"drift_min_us", finite(a.drift_min_us)},
                                      {"drift_median_us", finite(a.drift_median_us)},
                                      {"rx_span_s", finite(a.rx_span_s)},
                                      {"schedule_span_s", finite(a.schedule_span_s)},
                                      {"rx_pps", finite(a.rx_pps)}};
    return j.dump();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Receive a replayed capture with kernel timestamps and report the timing error against "
        "the capture's schedule (scripts/bench-replay)"};
    std::string pcap, json, label = "replay", make_long_out, errors_csv;
    std::vector<std::uint16_t> port_list;
    double long_seconds = 600;
    RxOptions o;
    app.add_option("--pcap", pcap, "The capture being replayed (the schedule)")->required();
    app.add_option("--ports", port_list, "Destination ports to receive (default: all in the pcap)")
        ->delimiter(',');
    app.add_option("--bind", o.bind, "Local IPv4 address to bind")->capture_default_str();
    app.add_option("--start-timeout", o.start_timeout_s, "Give up if nothing arrives (s)")
        ->capture_default_str();
    app.add_option("--idle", o.idle_s, "Stop this long after the last datagram (s)")
        ->capture_default_str();
    app.add_option("--ready", o.ready, "Create this file once the sockets are bound");
    app.add_flag("!--no-gro", o.gro,
                 "Do not ask for UDP GRO (each datagram then crosses the kernel on its own)");
    app.add_option("--json", json, "Write the result as one JSON object to this file");
    app.add_option("--label", label, "Name of the run in the output")->capture_default_str();
    app.add_option("--errors", errors_csv,
                   "Also write every matched datagram's timing error to this CSV (index, port, "
                   "schedule offset ns, error ns), to see which packets are late");
    app.add_option("--make-long", make_long_out,
                   "Instead of receiving: write a capture repeating --pcap for --seconds");
    app.add_option("--seconds", long_seconds, "Length of --make-long's capture")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        if (!make_long_out.empty()) return make_long(pcap, make_long_out, long_seconds);
        std::set<std::uint16_t> want(port_list.begin(), port_list.end()), seen;
        const auto sched = load_schedule(pcap, want, seen);
        if (sched.empty()) {
            std::fprintf(stderr, "udp-timing-rx: '%s': no UDP datagrams to the ports asked for\n",
                         pcap.c_str());
            return 1;
        }
        std::vector<int> fds;
        std::vector<std::uint16_t> ports(seen.begin(), seen.end());
        for (auto p : ports) {
            const int fd = open_socket(o.bind, p, o.rcvbuf, o.gro);
            if (fd < 0) {
                std::fprintf(stderr, "udp-timing-rx: cannot bind %s:%u: %s\n", o.bind.c_str(),
                             static_cast<unsigned>(p), std::strerror(errno));
                return 1;
            }
            fds.push_back(fd);
        }
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        if (!o.ready.empty()) std::ofstream(o.ready) << "ready\n";
        const auto rx = receive(fds, ports, sched.size(), o);
        for (int fd : fds) ::close(fd);
        std::vector<ErrorRow> rows;
        const Analysis a = analyse(sched, rx, errors_csv.empty() ? nullptr : &rows);
        if (!errors_csv.empty()) {
            std::ofstream f(errors_csv);
            f << "index,port,schedule_offset_ns,error_ns\n";
            for (const auto& r : rows)
                f << r.index << ',' << r.port << ',' << r.offset_ns << ',' << r.error_ns << '\n';
            if (!f) {
                std::fprintf(stderr, "udp-timing-rx: cannot write '%s'\n", errors_csv.c_str());
                return 1;
            }
        }
        std::printf(
            "udp-timing-rx %s: received %zu/%zu (matched %zu, lost %zu, unmatched %zu), error "
            "p50 %.1f p99 %.1f max %.1f min %.1f us, |error| p99 %.1f us, jitter p99 %.1f us, "
            "drift %.1f us (median %.1f us) over %.3f s, rx %.0f packets/s\n",
            label.c_str(), a.received, a.scheduled, a.matched, a.lost, a.unmatched, a.p50_us,
            a.p99_us, a.max_us, a.min_us, a.abs_p99_us, a.jitter_p99_us, a.drift_min_us,
            a.drift_median_us, a.schedule_span_s, a.rx_pps);
        if (!json.empty()) std::ofstream(json) << to_json(label, a) << "\n";
        return a.matched > 0 ? 0 : 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "udp-timing-rx: %s\n", e.what());
        return 1;
    }
}
