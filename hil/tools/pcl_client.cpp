// SPDX-License-Identifier: Apache-2.0
// mirage-pcl-client: an independent Velodyne client (PCL 1.13's VLPGrabber / HDLGrabber) that
// decodes a live UDP stream or a pcap and prints each revolution's point count and a summary.
// Issue 3 item 6; PCL's decoding rules and quirks: docs/wire-formats.md §5.1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <pcl/io/hdl_grabber.h>
#include <pcl/io/vlp_grabber.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mirage/pcap/pcap.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kVelodyneDataSize = 1206;  // the only payload size PCL accepts

// Sweep counts as PCL delivers them (from its consumer thread).
class SweepLog {
  public:
    explicit SweepLog(bool quiet) : quiet_(quiet) {}
    void on_sweep(const pcl::PointCloud<pcl::PointXYZI>::ConstPtr& cloud) {
        std::lock_guard lock(mutex_);
        counts_.push_back(cloud->size());
        if (!quiet_) {
            // PCL's first sweep starts wherever the stream started (usually a partial turn).
            std::printf("rev %zu: %zu points%s\n", counts_.size(), cloud->size(),
                        counts_.size() == 1 ? " (first, may be partial)" : "");
            std::fflush(stdout);
        }
    }
    std::vector<std::size_t> counts() const {
        std::lock_guard lock(mutex_);
        return counts_;
    }

  private:
    bool quiet_;
    mutable std::mutex mutex_;
    std::vector<std::size_t> counts_;
};

// A UDP socket bound to addr:port (port 0: the kernel picks one). -1 on failure.
int bind_udp(const std::string& addr, std::uint16_t port) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) return -1;
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(port);
    if (::inet_pton(AF_INET, addr.c_str(), &sa.sin_addr) != 1 ||
        ::bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

std::uint16_t local_port(int fd) {
    sockaddr_in sa{};
    socklen_t len = sizeof sa;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
    return ntohs(sa.sin_port);
}

void send_to_loopback(int fd, std::uint16_t port, const std::uint8_t* data, std::size_t n) {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::sendto(fd, data, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
}

// PCL's UDP reader blocks in receive_from and only checks its stop flag between datagrams, so
// stop() hangs on a silent socket. Stop it on a helper thread while nudging its port with
// 1-byte datagrams (PCL drops anything that is not 1206 bytes). False if it did not stop in time
// (the thread is then left behind; the process is about to exit anyway).
bool stop_udp_grabber(pcl::HDLGrabber& grabber, std::uint16_t port, Clock::duration timeout) {
    auto done = std::make_shared<std::atomic<bool>>(false);
    std::thread stopper([&grabber, done] {
        grabber.stop();
        done->store(true);
    });
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    const std::uint8_t nudge = 0;
    const auto deadline = Clock::now() + timeout;
    while (!done->load() && Clock::now() < deadline) {
        if (fd >= 0) send_to_loopback(fd, port, &nudge, 1);
        pollfd none{};
        ::poll(&none, 0, 5);  // pacing of the nudges only, not a wait for a result
    }
    if (fd >= 0) ::close(fd);
    if (done->load()) {
        stopper.join();
        return true;
    }
    stopper.detach();
    return false;
}

// PCL starts a new sweep whenever the azimuth decreases. Its isRunning() stays true after a pcap
// replay ends (PCL 1.13 keeps the reader thread until stop()), so the end of a replay is known
// from the file: one sweep per decrease of the block azimuth over the stream.
std::size_t count_azimuth_wraps(const std::vector<mirage::pcap::UdpDatagram>& datagrams) {
    std::size_t wraps = 0;
    int last = -1;
    for (const auto& d : datagrams) {
        if (d.payload.size() != kVelodyneDataSize) continue;
        for (std::size_t b = 0; b < 12; ++b) {
            const int az = d.payload[100 * b + 2] | (d.payload[100 * b + 3] << 8);
            if (last >= 0 && az < last) ++wraps;
            last = az;
        }
    }
    return wraps;
}

std::unique_ptr<pcl::HDLGrabber> make_grabber(const std::string& model, const std::string& pcap,
                                              const std::string& calibration,
                                              std::uint16_t udp_port) {
    const auto loopback = boost::asio::ip::address::from_string("127.0.0.1");
    if (model == "vlp16") {
        if (!pcap.empty()) return std::make_unique<pcl::VLPGrabber>(pcap);
        return std::make_unique<pcl::VLPGrabber>(loopback, udp_port);
    }
    // HDL-32E: PCL's built-in table; HDL-64E: PCL reads only its own db.xml corrections format.
    if (!pcap.empty()) return std::make_unique<pcl::HDLGrabber>(calibration, pcap);
    return std::make_unique<pcl::HDLGrabber>(loopback, udp_port, calibration);
}

}  // namespace

int main(int argc, char** argv) {
    std::string model = "vlp16", pcap_path, address = "0.0.0.0", calibration;
    std::uint16_t port = 2368;
    double seconds = 5.0;
    bool quiet = false;

    CLI::App app{
        "mirage-pcl-client: decode a Velodyne stream with PCL 1.13 (VLPGrabber for VLP-16, "
        "HDLGrabber for HDL-32E / HDL-64E) and print points per revolution.\n"
        "UDP: datagrams arriving on --address:--port are counted and relayed over loopback to "
        "PCL's grabber; pcap: PCL replays the file at capture speed."};
    app.add_option("--model", model, "vlp16 | hdl32e | hdl64e")
        ->check(CLI::IsMember({"vlp16", "hdl32e", "hdl64e"}));
    app.add_option("--pcap", pcap_path, "Decode this capture instead of listening")
        ->check(CLI::ExistingFile);
    app.add_option("--address", address, "UDP address to listen on (IPv4)");
    app.add_option("--port", port, "UDP data port")->check(CLI::Range(1, 65535));
    app.add_option("--calibration", calibration,
                   "PCL/VeloView db.xml corrections (required for hdl64e; PCL 1.13 cannot read "
                   "the ROS YAML that `mirage emulate --calibration-out` writes)")
        ->check(CLI::ExistingFile);
    app.add_option("--seconds", seconds, "Stop after this long (pcap: or at its end)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--quiet", quiet, "Only the summary line");
    CLI11_PARSE(app, argc, argv);
    if (model == "hdl64e" && calibration.empty()) {
        std::fprintf(stderr, "mirage-pcl-client: hdl64e needs --calibration (a db.xml)\n");
        return 2;
    }

    const auto t0 = Clock::now();
    const auto deadline =
        t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    SweepLog log(quiet);
    std::uint64_t packets = 0, other_datagrams = 0;
    std::size_t expected_sweeps = 0;  // pcap only
    std::unique_ptr<pcl::HDLGrabber> grabber;
    std::uint16_t pcl_port = 0;
    int listen_fd = -1, relay_fd = -1;

    if (!pcap_path.empty()) {
        try {
            const auto datagrams = mirage::pcap::read_udp(pcap_path);
            for (const auto& d : datagrams)
                (d.payload.size() == kVelodyneDataSize ? packets : other_datagrams)++;
            expected_sweeps = count_azimuth_wraps(datagrams);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "mirage-pcl-client: %s\n", e.what());
            return 1;
        }
    } else {
        listen_fd = bind_udp(address, port);
        // PCL listens on a loopback port the kernel picks (bound, read, closed, reused at once).
        relay_fd = bind_udp("127.0.0.1", 0);
        if (listen_fd < 0 || relay_fd < 0) {
            std::fprintf(stderr, "mirage-pcl-client: cannot bind udp %s:%u\n", address.c_str(),
                         static_cast<unsigned>(port));
            return 1;
        }
        pcl_port = local_port(relay_fd);
        ::close(relay_fd);
        relay_fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    }

    grabber = make_grabber(model, pcap_path, calibration, pcl_port);
    std::function<void(const pcl::PointCloud<pcl::PointXYZI>::ConstPtr&)> cb =
        [&log](const pcl::PointCloud<pcl::PointXYZI>::ConstPtr& c) { log.on_sweep(c); };
    grabber->registerCallback(cb);
    std::printf("mirage-pcl-client: %s on %s\n", grabber->getName().c_str(),
                pcap_path.empty() ? ("udp " + address + ":" + std::to_string(port)).c_str()
                                  : ("pcap " + pcap_path).c_str());
    std::fflush(stdout);
    grabber->start();

    bool stopped_cleanly = true;
    if (pcap_path.empty()) {
        std::vector<std::uint8_t> buf(65536);
        while (Clock::now() < deadline) {
            pollfd p{listen_fd, POLLIN, 0};
            const auto left =
                std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
            if (::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(left.count(), 0))) <= 0)
                continue;
            const ssize_t n = ::recv(listen_fd, buf.data(), buf.size(), 0);
            if (n <= 0) continue;
            const auto size = static_cast<std::size_t>(n);
            (size == kVelodyneDataSize ? packets : other_datagrams)++;
            if (size == kVelodyneDataSize) send_to_loopback(relay_fd, pcl_port, buf.data(), size);
        }
        stopped_cleanly = stop_udp_grabber(*grabber, pcl_port, std::chrono::seconds(2));
        ::close(listen_fd);
        ::close(relay_fd);
    } else {
        // PCL replays at capture speed; done once every azimuth wrap has produced its sweep
        // (the packets after the last wrap never make a sweep: PCL does not flush at the end).
        while (log.counts().size() < expected_sweeps && Clock::now() < deadline) {
            pollfd none{};
            ::poll(&none, 0, 10);
        }
        grabber->stop();
    }

    const auto counts = log.counts();
    // Mean over the revolutions after the first (PCL's first sweep starts mid-turn; the
    // trailing partial one is never emitted).
    double mean = 0;
    if (counts.size() > 1) {
        for (std::size_t i = 1; i < counts.size(); ++i) mean += static_cast<double>(counts[i]);
        mean /= static_cast<double>(counts.size() - 1);
    }
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf(
        "mirage-pcl-client: %zu revolutions, mean %.0f points/rev (excluding the first), "
        "%llu data packets, %llu other datagrams, %.1f s\n",
        counts.size(), mean, static_cast<unsigned long long>(packets),
        static_cast<unsigned long long>(other_datagrams), elapsed);
    std::fflush(stdout);
    if (!stopped_cleanly) {
        std::fprintf(stderr, "mirage-pcl-client: PCL's grabber did not stop; exiting anyway\n");
        std::_Exit(counts.empty() ? 1 : 0);
    }
    return counts.empty() ? 1 : 0;
}
