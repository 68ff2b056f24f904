// SPDX-License-Identifier: Apache-2.0
// Encoder throughput per model and return mode: returns → data packets (packets/s), and the
// decoder's for comparison. Not a test: run by hand or by the lead's benchmark wiring.
#include <benchmark/benchmark.h>

#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

void BM_Encode(benchmark::State& state) {
    const Model model = static_cast<Model>(state.range(0));
    const auto mode = static_cast<ReturnMode>(state.range(1));
    const ModelDescriptor& md = descriptor(model);
    const sensor::SensorModel s = test::preset_at(md, 600);
    std::uint64_t packets = 0;
    PacketizerOptions o;
    o.position_packets = false;
    Packetizer pk(
        md, mode, s, {}, [&](const wire::PacketView&) { ++packets; }, o);
    // 64 packets of returns (every pulse hit, 2 returns in dual mode), replayed with shifted
    // pulse numbers so the packetizer keeps encoding new packets.
    const std::uint64_t n = 64 * pk.pulses_per_packet();
    test::SyntheticOptions so;
    so.miss_probability = 0.1;
    so.max_returns = mode == ReturnMode::Dual ? 2 : 1;
    so.max_range_m = 90;
    auto pts = test::synthetic_returns(*s.scan, n, {}, so);
    std::uint64_t base = 0;
    for (auto _ : state) {
        for (auto& p : pts) p.pulse += base ? n : 0;
        base = 1;
        pk.add(pts);
        pk.advance_to(pts.back().pulse - pts.back().pulse % pk.pulses_per_packet() +
                      pk.pulses_per_packet());
    }
    state.counters["packets/s"] =
        benchmark::Counter(static_cast<double>(packets), benchmark::Counter::kIsRate);
    state.SetLabel(std::string(md.name) + " " + to_string(mode));
}

void BM_Decode(benchmark::State& state) {
    const Model model = static_cast<Model>(state.range(0));
    const ModelDescriptor& md = descriptor(model);
    const sensor::SensorModel s = test::preset_at(md, 600);
    std::vector<test::CollectedPacket> out;
    PacketizerOptions o;
    o.position_packets = false;
    Packetizer pk(md, ReturnMode::Strongest, s, {}, test::collect_into(out), o);
    const std::uint64_t n = 16 * pk.pulses_per_packet();
    pk.add(test::synthetic_returns(*s.scan, n, {}, {}));
    pk.advance_to(n);
    DecodedPacket d;
    std::uint64_t packets = 0;
    for (auto _ : state) {
        for (const auto& p : out) {
            benchmark::DoNotOptimize(decode_data(p.bytes, &md, d));
            ++packets;
        }
    }
    state.counters["packets/s"] =
        benchmark::Counter(static_cast<double>(packets), benchmark::Counter::kIsRate);
    state.SetLabel(std::string(md.name));
}

void all_models(benchmark::internal::Benchmark* b) {
    for (Model m : kAllModels)
        for (ReturnMode r : {ReturnMode::Strongest, ReturnMode::Dual})
            b->Args({static_cast<int>(m), static_cast<int>(r)});
}

BENCHMARK(BM_Encode)->Apply(all_models);
BENCHMARK(BM_Decode)->DenseRange(0, 4);

}  // namespace
}  // namespace mirage::velodyne

BENCHMARK_MAIN();
