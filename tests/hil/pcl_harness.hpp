// SPDX-License-Identifier: Apache-2.0
// Test plumbing for driving PCL's Velodyne grabbers against `mirage emulate`: a child process with
// a deadline, a free UDP port, a sweep collector, and a stop() that cannot hang.
#pragma once
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pcl/io/hdl_grabber.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mirage/pcap/pcap.hpp"

namespace mirage::test {

using SteadyClock = std::chrono::steady_clock;

// Waits between polls of a condition (the condition, not this pause, decides when we go on).
inline void poll_pause() {
    pollfd none{};
    ::poll(&none, 0, 10);
}

// `mirage <args>` as a child process, stdout and stderr into a file.
class MirageProcess {
  public:
    MirageProcess(const std::vector<std::string>& args, std::string log_path)
        : log_(std::move(log_path)) {
        // Everything the child needs is built before fork(): PCL's threads may be running, and
        // the child must not allocate between fork() and exec().
        args_.push_back(MIRAGE_EXE);
        args_.insert(args_.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (auto& a : args_) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_ = ::fork();
        if (pid_ == 0) {
            const int fd = ::open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) {
                ::dup2(fd, 1);
                ::dup2(fd, 2);
            }
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
    }
    ~MirageProcess() {
        if (pid_ > 0 && !exited_) {
            ::kill(pid_, SIGKILL);  // our own child, by its id
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
    }
    MirageProcess(const MirageProcess&) = delete;
    MirageProcess& operator=(const MirageProcess&) = delete;

    // Exit code once the child ended before `timeout`; -1 if still running (then killed) or not
    // started.
    int wait(std::chrono::milliseconds timeout) {
        if (pid_ <= 0) return -1;
        const auto deadline = SteadyClock::now() + timeout;
        while (!exited_) {
            int status = 0;
            const pid_t r = ::waitpid(pid_, &status, WNOHANG);
            if (r == pid_) {
                exited_ = true;
                code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
                break;
            }
            if (SteadyClock::now() >= deadline) return -1;
            poll_pause();
        }
        return code_;
    }
    std::string output() const {
        std::ifstream in(log_);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }

  private:
    std::string log_;
    std::vector<std::string> args_;
    pid_t pid_ = -1;
    bool exited_ = false;
    int code_ = -1;
};

// A UDP port free right now on 127.0.0.1: bind port 0, read the number, close (PCL's grabber
// needs a number, not a socket).
inline std::uint16_t pick_free_udp_port() {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    sa.sin_port = 0;
    ::bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa);
    socklen_t len = sizeof sa;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
    ::close(fd);
    return ntohs(sa.sin_port);
}

// Every sweep PCL emits, in order (PCL calls back from its consumer thread).
class SweepCollector {
  public:
    using Cloud = pcl::PointCloud<pcl::PointXYZI>;
    void attach(pcl::HDLGrabber& g) {
        std::function<void(const Cloud::ConstPtr&)> cb = [this](const Cloud::ConstPtr& c) {
            std::lock_guard lock(mutex_);
            sweeps_.push_back(c);
        };
        g.registerCallback(cb);
    }
    std::size_t count() const {
        std::lock_guard lock(mutex_);
        return sweeps_.size();
    }
    std::vector<Cloud::ConstPtr> sweeps() const {
        std::lock_guard lock(mutex_);
        return sweeps_;
    }
    // True once at least n sweeps arrived before the deadline.
    bool wait_for(std::size_t n, std::chrono::milliseconds timeout) const {
        const auto deadline = SteadyClock::now() + timeout;
        while (count() < n) {
            if (SteadyClock::now() >= deadline) return false;
            poll_pause();
        }
        return true;
    }

  private:
    mutable std::mutex mutex_;
    std::vector<Cloud::ConstPtr> sweeps_;
};

// PCL starts a sweep whenever the azimuth decreases, so a stream yields one sweep per decrease of
// the block azimuth (the first block opens an empty sweep, the packets after the last wrap never
// make one: PCL does not flush). PCL 1.13's isRunning() stays true after a pcap replay (the reader
// thread is kept until stop()), so this count is how a test knows the replay is complete.
inline std::size_t count_azimuth_wraps(const std::vector<pcap::UdpDatagram>& datagrams) {
    std::size_t wraps = 0;
    int last = -1;
    for (const auto& d : datagrams) {
        if (d.payload.size() != 1206) continue;
        for (std::size_t b = 0; b < 12; ++b) {
            const int az = d.payload[100 * b + 2] | (d.payload[100 * b + 3] << 8);
            if (last >= 0 && az < last) ++wraps;
            last = az;
        }
    }
    return wraps;
}

// PCL's UDP reader blocks in receive_from and checks its stop flag only between datagrams, so
// stop() on a silent port hangs (PCL 1.13 quirk). Stop on a helper thread while sending 1-byte
// datagrams to the port (PCL drops every payload that is not 1206 bytes). False on timeout; the
// helper is then detached and the grabber must be leaked by the caller.
inline bool stop_udp_grabber(pcl::HDLGrabber& g, std::uint16_t port,
                             std::chrono::milliseconds timeout) {
    auto done = std::make_shared<std::atomic<bool>>(false);
    std::thread stopper([&g, done] {
        g.stop();
        done->store(true);
    });
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const std::uint8_t nudge = 0;
    const auto deadline = SteadyClock::now() + timeout;
    while (!done->load() && SteadyClock::now() < deadline) {
        ::sendto(fd, &nudge, 1, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
        poll_pause();
    }
    ::close(fd);
    if (!done->load()) {
        stopper.detach();
        return false;
    }
    stopper.join();
    return true;
}

}  // namespace mirage::test
