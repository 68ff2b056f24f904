// SPDX-License-Identifier: Apache-2.0
// mirage-sched-gaps: how often this machine takes the CPU away from a thread that only reads the
// clock. Any user-space sender is late by at least the rest of such a gap when a send time falls
// inside it, so the share of instants delayed by more than X bounds what a replay or a fake
// sensor can reach on this machine (scripts/bench-replay prints it beside the timing results).
// With --threads N, one spinning thread per CPU: were the CPUs held off together (a virtual
// machine descheduled whole), no second sending thread could cover for the first.
#include <pthread.h>
#include <sched.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "gap_overlap.hpp"
#include "gap_period.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/hostclock/keep_awake.hpp"
#include "spin_gaps.hpp"

using mirage::hil::Gap;

int main(int argc, char** argv) {
    CLI::App app{"Measure the scheduling gaps a spinning thread sees on this machine"};
    double seconds = 10;
    unsigned threads = 1;
    std::string json;
    bool keep_awake = false;
    app.add_option("--seconds", seconds, "How long to spin")->capture_default_str();
    app.add_option("--threads", threads,
                   "Spinning threads, pinned one per CPU when more than one; also reports the "
                   "instants when all of them were held off at once")
        ->capture_default_str();
    app.add_option("--json", json, "Also write the result as one JSON object to this file");
    app.add_flag("--keep-awake", keep_awake,
                 "Spin on the CPU that `mirage replay --keep-awake` sends from, kept out of idle "
                 "as it keeps it (one thread only; docs/time.md §5)");
    CLI11_PARSE(app, argc, argv);
    if (!(seconds > 0) || seconds > 3600) {
        std::fprintf(stderr, "mirage-sched-gaps: --seconds must be in (0, 3600]\n");
        return 2;
    }
    const unsigned cpus = std::max(1u, std::thread::hardware_concurrency());
    if (threads < 1 || threads > cpus) {
        std::fprintf(stderr, "mirage-sched-gaps: --threads must be in [1, %u] (CPUs)\n", cpus);
        return 2;
    }
    if (keep_awake && threads != 1) {
        std::fprintf(stderr, "mirage-sched-gaps: --keep-awake measures one thread\n");
        return 2;
    }
    const int awake_cpu = mirage::hostclock::sending_cpu();
    const mirage::hostclock::KeepAwake awake(keep_awake ? std::vector<int>{awake_cpu}
                                                        : std::vector<int>{});
    // All threads spin over the same span, starting 10 ms from now (after they have started).
    const std::int64_t start = mirage::hostclock::monotonic_ns() + 10'000'000;
    const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
    std::vector<std::vector<Gap>> gaps(threads);
    std::vector<int> pin_error(threads, 0);
    std::vector<std::thread> pool;
    for (unsigned c = 0; c < threads; ++c) {
        pool.emplace_back([&, c] {
            std::string why;
            if (keep_awake && !mirage::hostclock::pin_current_thread(awake_cpu, why)) {
                pin_error[c] = EINVAL;
                return;
            }
            if (threads > 1) {
                cpu_set_t set;
                CPU_ZERO(&set);
                CPU_SET(c, &set);
                pin_error[c] = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
                if (pin_error[c] != 0) return;
            }
            gaps[c] = mirage::hil::spin_gaps(start, end);
        });
    }
    for (auto& t : pool) t.join();
    for (unsigned c = 0; c < threads; ++c) {
        if (pin_error[c] != 0) {
            std::fprintf(stderr, "mirage-sched-gaps: cannot pin a thread to CPU %d: %s\n",
                         keep_awake ? awake_cpu : static_cast<int>(c), std::strerror(pin_error[c]));
            return 1;
        }
    }
    const std::span<const std::vector<Gap>> all(gaps);

    constexpr std::int64_t kThresholds[] = {10'000, 20'000, 50'000, 100'000};
    const double span = static_cast<double>(end - start);
    // Share of instants (%) that the given threads all reach more than thresholds[k] late.
    const auto pct = [&](std::span<const std::vector<Gap>> g) {
        std::array<double, 4> out{};
        for (int k = 0; k < 4; ++k)
            out[k] =
                100.0 * static_cast<double>(mirage::hil::delayed_for_all(g, kThresholds[k])) / span;
        return out;
    };
    std::vector<std::array<double, 4>> thread_pct;  // each thread alone
    for (unsigned c = 0; c < threads; ++c) thread_pct.push_back(pct(all.subspan(c, 1)));
    const std::array<double, 4> all_pct = threads > 1 ? pct(all) : thread_pct[0];
    std::int64_t count[4] = {}, worst = 0;
    for (const Gap& x : gaps[0]) {
        worst = std::max(worst, x.end - x.begin);
        for (int k = 0; k < 4; ++k) count[k] += x.end - x.begin > kThresholds[k];
    }
    auto rate = [&](int k) { return static_cast<double>(count[k]) / (span * 1e-9); };
    const std::array<double, 4>& first = thread_pct[0];
    std::printf(
        "sched-gaps: %.1f s spinning: gaps > 10/20/50/100 us: %.0f/%.0f/%.0f/%.0f per s, worst "
        "%.1f us; instants delayed > 10/20/50/100 us: %.2f/%.2f/%.3f/%.3f %%\n",
        span * 1e-9, rate(0), rate(1), rate(2), rate(3), static_cast<double>(worst) * 1e-3,
        first[0], first[1], first[2], first[3]);
    // Of the first thread's gaps: the 20 µs threshold is the replay target's.
    const mirage::hil::GapPeriod period = mirage::hil::gap_period(gaps[0], kThresholds[1]);
    if (period.period_ns > 0)
        std::printf(
            "sched-gaps: %zu gaps > 20 us; most common spacing %.3f ms (%.0f %% of the spacings "
            "within ~15 us of it); %.0f %% of the gaps at one phase of it (a tenth of the period "
            "wide: ~10 %% for gaps at random times)\n",
            period.gaps, period.period_ns * 1e-6, 100.0 * period.spacing_share,
            100.0 * period.phase_share);
    else
        std::printf("sched-gaps: %zu gaps > 20 us: too few for a period\n", period.gaps);
    if (keep_awake)
        std::printf("sched-gaps: on CPU %d, kept out of idle by a SCHED_IDLE spinner\n", awake_cpu);
    if (threads > 1) {
        for (unsigned c = 1; c < threads; ++c) {
            const std::array<double, 4>& p = thread_pct[c];
            std::printf(
                "sched-gaps: thread on CPU %u: instants delayed > 10/20/50/100 us: "
                "%.2f/%.2f/%.3f/%.3f %%\n",
                c, p[0], p[1], p[2], p[3]);
        }
        // What independent CPUs would give: the product of the threads' shares.
        double independent = 1;
        for (const auto& p : thread_pct) independent *= p[1] / 100.0;
        std::printf(
            "sched-gaps: all %u threads at once: instants delayed > 10/20/50/100 us: "
            "%.2f/%.2f/%.3f/%.3f %% (> 20 us if the CPUs were held off independently: %.4f %%)\n",
            threads, all_pct[0], all_pct[1], all_pct[2], all_pct[3], 100.0 * independent);
    }
    if (!json.empty()) {
        // NaN or Inf (no gaps, no period) becomes null: never a number JSON cannot hold.
        const auto finite = [](double v) {
            return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
        };
        const nlohmann::ordered_json j = {
            {"seconds", finite(double(span) * 1e-9)},
            {"threads", threads},
            {"gaps_per_s_over_20us", finite(rate(1))},
            {"gaps_per_s_over_50us", finite(rate(2))},
            {"worst_us", finite(static_cast<double>(worst) * 1e-3)},
            {"delayed_pct_over_10us", finite(first[0])},
            {"delayed_pct_over_20us", finite(first[1])},
            {"delayed_pct_over_50us", finite(first[2])},
            {"delay_p99_us", finite(static_cast<double>(mirage::hil::delay_exceeded_by(
                                        gaps[0], end - start, 0.01)) *
                                    1e-3)},
            {"keep_awake", keep_awake},
            {"all_threads_delayed_pct_over_20us", finite(all_pct[1])},
            {"all_threads_delayed_pct_over_50us", finite(all_pct[2])},
            {"gap_period_ms_over_20us", finite(period.period_ns * 1e-6)},
            {"gap_phase_share_pct_over_20us", finite(100.0 * period.phase_share)}};
        std::ofstream f(json);
        f << j.dump() << "\n";
        if (!f) {
            std::fprintf(stderr, "mirage-sched-gaps: cannot write %s\n", json.c_str());
            return 1;
        }
    }
    return 0;
}
