// SPDX-License-Identifier: Apache-2.0
// Pacing benchmark: loopback UDP at a fixed rate, lateness measured from kernel timestamps.
//   mirage_pacing_probe [--rate 10000] [--seconds 60] [--size 1206] [--fifo 10]
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "mirage/core/error.hpp"
#include "mirage/udp/pacing_probe.hpp"

int main(int argc, char** argv) {
    CLI::App app{"Loopback UDP pacing probe: p50/p99/max lateness against the schedule"};
    std::uint32_t rate = 10'000;
    double seconds = 60;
    std::size_t size = 1206;
    int fifo = 0;
    app.add_option("--rate", rate, "packets per second")->check(CLI::Range(1u, 1'000'000u));
    app.add_option("--seconds", seconds, "duration")->check(CLI::Range(0.001, 86400.0));
    app.add_option("--size", size, "payload bytes")->check(CLI::Range(8ul, 65507ul));
    app.add_option("--fifo", fifo, "SCHED_FIFO priority of the sending thread (0: normal)")
        ->check(CLI::Range(0, 99));
    CLI11_PARSE(app, argc, argv);
    mirage::udp::PacingProbeConfig config;
    config.rate_hz = rate;
    config.packets = static_cast<std::uint64_t>(seconds * rate);
    config.payload_bytes = size;
    config.fifo_priority = fifo;
    try {
        const auto report = mirage::udp::run_pacing_probe(config);
        fmt::print("{}\n", mirage::udp::format_report(report));
        return report.received == report.scheduled ? 0 : 1;
    } catch (const mirage::Error& e) {
        fmt::print(stderr, "{}\n", e.what());
        return 2;
    }
}
