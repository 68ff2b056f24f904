// SPDX-License-Identifier: Apache-2.0
#include "mirage/hostclock/keep_awake.hpp"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cerrno>
#include <cstring>
#include <latch>

namespace mirage::hostclock {

bool pin_current_thread(int cpu, std::string& why);

namespace {

// Lowers the calling thread to SCHED_IDLE and pins it to `cpu`; the reason when either fails
// (the thread must then not spin: an ordinary spinner would take half the sender's CPU).
std::string become_idle_spinner(int cpu) {
    sched_param p{};
    if (const int rc = pthread_setschedparam(pthread_self(), SCHED_IDLE, &p); rc != 0)
        return std::string("SCHED_IDLE: ") + std::strerror(rc);
    std::string pin;
    if (!pin_current_thread(cpu, pin)) return "pin " + pin;
    return {};
}

}  // namespace

std::vector<int> allowed_cpus() {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    std::vector<int> cpus;
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return cpus;
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
        if (CPU_ISSET(cpu, &allowed)) cpus.push_back(cpu);
    return cpus;
}

int sending_cpu() {
    const std::vector<int> cpus = allowed_cpus();
    return cpus.empty() ? 0 : cpus.back();
}

bool pin_current_thread(int cpu, std::string& why) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    const int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    if (rc != 0) why = "cpu " + std::to_string(cpu) + ": " + std::strerror(rc);
    return rc == 0;
}

KeepAwake::KeepAwake(const std::vector<int>& cpus) : cpus_(cpus) {
    // Each thread settles its policy before the constructor returns, so warning() is final.
    std::vector<std::string> why(cpus.size());
    std::latch settled(static_cast<std::ptrdiff_t>(cpus.size()));
    std::size_t started = 0;
    try {
        for (; started < cpus.size(); ++started) {
            threads_.emplace_back([this, cpu = cpus[started], &out = why[started], &settled] {
                pthread_setname_np(pthread_self(), "mirage-awake");  // for top and ps
                out = become_idle_spinner(cpu);
                const bool spin = out.empty();
                settled.count_down();
                while (spin && !stop_.load(std::memory_order_relaxed)) cpu_relax();
            });
        }
    } catch (...) {  // no thread: the ones started must not outlive `why` and `settled`
        settled.count_down(static_cast<std::ptrdiff_t>(cpus.size() - started));
        settled.wait();
        stop_.store(true, std::memory_order_relaxed);
        for (auto& t : threads_) t.join();
        throw;
    }
    settled.wait();
    for (std::size_t i = 0; i < cpus.size() && warning_.empty(); ++i)
        if (!why[i].empty()) warning_ = "cpu " + std::to_string(cpus[i]) + ": " + why[i];
}

double KeepAwake::cpu_seconds() const {
    double s = 0;
    for (const auto& t : threads_) {
        clockid_t id{};
        timespec ts{};
        // native_handle() is not const; the handle itself is only read.
        if (pthread_getcpuclockid(const_cast<std::thread&>(t).native_handle(), &id) == 0 &&
            clock_gettime(id, &ts) == 0)
            s += double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
    }
    return s;
}

KeepAwake::~KeepAwake() {
    stop_.store(true, std::memory_order_relaxed);
    for (auto& t : threads_) t.join();
}

}  // namespace mirage::hostclock
