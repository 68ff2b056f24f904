// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <string>
#include <thread>
#include <vector>

namespace mirage::hostclock {

// The pause hint of a spin loop: it leaves the core's execution units to a hyper-thread sibling.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

// The CPUs this process may run on (its affinity mask), ascending.
std::vector<int> allowed_cpus();
// The CPU a real-time run's sending thread is pinned to under --keep-awake: the last allowed one
// (CPU 0 takes more of the machine's interrupts).
int sending_cpu();
// Pins the calling thread to `cpu`; false and why when the kernel refuses.
bool pin_current_thread(int cpu, std::string& why);

// Keeps CPUs out of their idle state while a real-time run lasts: one SCHED_IDLE thread per
// listed CPU, pinned to it, spinning on the pause hint. A CPU that halts
// wakes late for the next timer (on a virtual machine the host must first run the halted vCPU
// again: hundreds of µs at p99); a CPU that always runs something takes the timer at once.
// SCHED_IDLE threads give way to any other thread the moment it becomes runnable, so rendering
// loses almost nothing, but every CPU reads 100 % busy. The user-space form of `idle=poll`;
// docs/time.md §5 has the measurements.
class KeepAwake {
  public:
    // Empty: does nothing. Commands keep only the sending thread's CPU awake (sending_cpu()):
    // a guest whose vCPUs never idle is descheduled by its host for longer (docs/time.md §5).
    explicit KeepAwake(const std::vector<int>& cpus);
    ~KeepAwake();
    KeepAwake(const KeepAwake&) = delete;
    KeepAwake& operator=(const KeepAwake&) = delete;

    // Threads started, one per CPU listed.
    std::size_t threads() const { return threads_.size(); }
    const std::vector<int>& cpus() const { return cpus_; }
    // Why a thread runs without SCHED_IDLE or unpinned (empty when all went as planned).
    const std::string& warning() const { return warning_; }
    // CPU seconds the spinners have used so far: benchmarks take it out of the process's.
    double cpu_seconds() const;

  private:
    std::atomic<bool> stop_{false};
    std::vector<int> cpus_;
    std::vector<std::thread> threads_;
    std::string warning_;
};

// The CPU a sending thread is pinned to: the first one `awake` keeps awake; -1 without one.
inline int sending_cpu_of(const KeepAwake* awake) {
    return awake && !awake->cpus().empty() ? awake->cpus().front() : -1;
}

}  // namespace mirage::hostclock
