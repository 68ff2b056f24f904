// SPDX-License-Identifier: Apache-2.0
// Encoder throughput: lidar packets per second through OusterPacketizer (returns → bytes), per
// profile and mode. `bench_ouster --benchmark_filter=...`; the lead wires it into the report.
#include <benchmark/benchmark.h>

#include "mirage/ouster/packetizer.hpp"
#include "ouster_test_util.hpp"

namespace {

using namespace mirage;
using namespace mirage::ouster;

constexpr const char* kPresets[] = {"os1-64-1024x10", "os1-128-2048x10", "os0-32-512x20",
                                    "os2-128-1024x20"};
constexpr Profile kProfiles[] = {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16,
                                 Profile::Rng15Rfl8Nir8};

void BM_OusterEncode(benchmark::State& state) {
    const Descriptor d = make_descriptor(kPresets[state.range(0)], kProfiles[state.range(1)]);
    const std::uint64_t packets = 64;
    const std::uint64_t pulses = packets * d.columns_per_packet * d.beams;
    auto pts = test::random_returns(d, pulses, 200.0, 7);
    std::uint64_t bytes = 0, sent = 0, base = 0;
    OusterPacketizer pk(d, {}, [&](const wire::PacketView& v) {
        bytes += v.bytes.size();
        ++sent;
    });
    for (auto _ : state) {
        // Shift the same returns to the next 64 packets (pulse numbers keep increasing).
        for (auto& p : pts) p.pulse += base ? pulses : 0;
        base += pulses;
        pk.add(pts);
        pk.advance_to(base);
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(sent));
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
    state.SetLabel(std::string(kPresets[state.range(0)]) + " " + to_string(d.profile));
}
BENCHMARK(BM_OusterEncode)->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
