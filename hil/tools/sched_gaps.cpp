// SPDX-License-Identifier: Apache-2.0
// mirage-sched-gaps: how often this machine takes the CPU away from a thread that only reads the
// clock. Any user-space sender is late by at least the rest of such a gap when a send time falls
// inside it, so the share of instants delayed by more than X bounds what a replay or a fake
// sensor can reach on this machine (scripts/bench-replay prints it beside the timing results).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>

namespace {

std::int64_t monotonic_ns() {
    timespec t{};
    ::clock_gettime(CLOCK_MONOTONIC, &t);
    return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Measure the scheduling gaps a spinning thread sees on this machine"};
    double seconds = 10;
    std::string json;
    app.add_option("--seconds", seconds, "How long to spin")->capture_default_str();
    app.add_option("--json", json, "Also write the result as one JSON object to this file");
    CLI11_PARSE(app, argc, argv);
    if (!(seconds > 0) || seconds > 3600) {
        std::fprintf(stderr, "mirage-sched-gaps: --seconds must be in (0, 3600]\n");
        return 2;
    }
    // A gap = time between two consecutive clock reads above 5 µs (a read takes ~20 ns).
    // delayed[k]: total time of instants that a thread would reach later than thresholds[k].
    constexpr std::int64_t kThresholds[] = {10'000, 20'000, 50'000, 100'000};
    std::int64_t count[4] = {}, delayed[4] = {}, worst = 0;
    const std::int64_t start = monotonic_ns();
    const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
    std::int64_t prev = start, now = start;
    while ((now = monotonic_ns()) < end) {
        const std::int64_t gap = now - prev;
        prev = now;
        if (gap < 5'000) continue;
        if (gap > worst) worst = gap;
        for (int k = 0; k < 4; ++k) {
            if (gap > kThresholds[k]) {
                ++count[k];
                delayed[k] += gap - kThresholds[k];
            }
        }
    }
    const double span = static_cast<double>(now - start);
    auto pct = [&](int k) { return 100.0 * static_cast<double>(delayed[k]) / span; };
    auto rate = [&](int k) { return static_cast<double>(count[k]) / (span * 1e-9); };
    std::printf(
        "sched-gaps: %.1f s spinning: gaps > 10/20/50/100 us: %.0f/%.0f/%.0f/%.0f per s, worst "
        "%.1f us; instants delayed > 10/20/50/100 us: %.2f/%.2f/%.3f/%.3f %%\n",
        span * 1e-9, rate(0), rate(1), rate(2), rate(3), static_cast<double>(worst) * 1e-3, pct(0),
        pct(1), pct(2), pct(3));
    if (!json.empty()) {
        std::ofstream f(json);
        f << "{\"seconds\": " << span * 1e-9 << ", \"gaps_per_s_over_20us\": " << rate(1)
          << ", \"gaps_per_s_over_50us\": " << rate(2)
          << ", \"worst_us\": " << static_cast<double>(worst) * 1e-3
          << ", \"delayed_pct_over_10us\": " << pct(0) << ", \"delayed_pct_over_20us\": " << pct(1)
          << ", \"delayed_pct_over_50us\": " << pct(2) << "}\n";
        if (!f) {
            std::fprintf(stderr, "mirage-sched-gaps: cannot write %s\n", json.c_str());
            return 1;
        }
    }
    return 0;
}
