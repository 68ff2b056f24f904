// SPDX-License-Identifier: Apache-2.0
// KeepAwake (docs/time.md §5): one SCHED_IDLE spinner pinned to each CPU listed, gone when it
// goes out of scope, and giving way to ordinary threads.
#include "mirage/hostclock/keep_awake.hpp"

#include <dirent.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "mirage/hostclock/host_clock.hpp"

namespace {

using mirage::hostclock::KeepAwake;

// The ids of this process's threads named `name` (/proc/self/task/*/comm).
std::vector<pid_t> threads_named(const std::string& name) {
    std::vector<pid_t> out;
    DIR* d = opendir("/proc/self/task");
    if (d == nullptr) return out;
    while (const dirent* e = readdir(d)) {
        if (e->d_name[0] == '.') continue;
        std::ifstream f(std::string("/proc/self/task/") + e->d_name + "/comm");
        std::string comm;
        std::getline(f, comm);
        if (comm == name) out.push_back(static_cast<pid_t>(std::stoi(e->d_name)));
    }
    closedir(d);
    return out;
}

TEST(KeepAwake, NoCpusStartsNothing) {
    const KeepAwake awake(std::vector<int>{});
    EXPECT_EQ(awake.threads(), 0u);
    EXPECT_TRUE(threads_named("mirage-awake").empty());
}

TEST(KeepAwake, SendingCpuIsTheLastAllowed) {
    const std::vector<int> cpus = mirage::hostclock::allowed_cpus();
    ASSERT_FALSE(cpus.empty());
    EXPECT_EQ(mirage::hostclock::sending_cpu(), cpus.back());
    std::thread([&] {
        std::string why;
        ASSERT_TRUE(mirage::hostclock::pin_current_thread(cpus.back(), why)) << why;
        EXPECT_EQ(sched_getcpu(), cpus.back());
        EXPECT_FALSE(mirage::hostclock::pin_current_thread(CPU_SETSIZE - 1, why));
        EXPECT_NE(why, "");
    }).join();
}

TEST(KeepAwake, OneIdlePinnedSpinnerPerCpuUntilDestroyed) {
    {
        const std::vector<int> cpus = mirage::hostclock::allowed_cpus();
        const KeepAwake awake(cpus);
        EXPECT_EQ(awake.threads(), cpus.size());
        EXPECT_EQ(awake.warning(), "");
        const std::vector<pid_t> tids = threads_named("mirage-awake");
        ASSERT_EQ(tids.size(), awake.threads());
        std::vector<int> pinned_to;
        for (const pid_t tid : tids) {
            EXPECT_EQ(sched_getscheduler(tid), SCHED_IDLE) << "thread " << tid;
            cpu_set_t set;
            CPU_ZERO(&set);
            ASSERT_EQ(sched_getaffinity(tid, sizeof set, &set), 0);
            EXPECT_EQ(CPU_COUNT(&set), 1) << "thread " << tid;
            for (int c = 0; c < CPU_SETSIZE; ++c)
                if (CPU_ISSET(c, &set)) pinned_to.push_back(c);
        }
        std::sort(pinned_to.begin(), pinned_to.end());
        EXPECT_EQ(pinned_to, cpus) << "one spinner on each CPU listed";
    }
    // A joined thread leaves /proc/self/task a moment after pthread_join returns.
    for (int i = 0; i < 100 && !threads_named("mirage-awake").empty(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_TRUE(threads_named("mirage-awake").empty());
}

// An ordinary thread and a spinner pinned to the same CPU: a SCHED_OTHER spinner would take
// half of it (equal weights); SCHED_IDLE's weight is 3 against 1024, so the spinner gets well
// under 1 % of what the ordinary thread gets. A ratio of the two, so other work on the machine
// (ctest runs tests in parallel) scales both alike.
TEST(KeepAwake, OrdinaryThreadsKeepTheirCpu) {
    const int cpu = mirage::hostclock::sending_cpu();
    double busy_s = 0, spinner_s = 0;
    std::thread([&] {
        std::string why;
        ASSERT_TRUE(mirage::hostclock::pin_current_thread(cpu, why)) << why;
        const KeepAwake awake(std::vector<int>{cpu});
        const double spin0 = awake.cpu_seconds();
        timespec a{}, b{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
        const std::int64_t end = mirage::hostclock::monotonic_ns() + 300'000'000;
        while (mirage::hostclock::monotonic_ns() < end) {
        }
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
        spinner_s = awake.cpu_seconds() - spin0;
        busy_s = double(b.tv_sec - a.tv_sec) + double(b.tv_nsec - a.tv_nsec) * 1e-9;
    }).join();
    std::printf("on CPU %d for 0.3 s: busy thread %.4f s CPU, SCHED_IDLE spinner %.4f s\n", cpu,
                busy_s, spinner_s);
    ASSERT_GT(busy_s, 0.03);
    EXPECT_LT(spinner_s, 0.05 * busy_s);
}

}  // namespace
