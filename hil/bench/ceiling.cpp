// SPDX-License-Identifier: Apache-2.0
#include "ceiling.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <queue>
#include <span>
#include <thread>

#include "mirage/render/trace_batches.hpp"

namespace mirage::hil {
namespace {

using Clock = std::chrono::steady_clock;

// One worker: chunks in turn from `next`, each chunk's tracing seconds into seconds[c].
void trace_chunks(const render::Setup& setup, const render::ChunkPlan& plan,
                  std::atomic<std::uint64_t>& next, std::atomic<std::uint64_t>& rays,
                  std::vector<double>& seconds) {
    render::TraceBatches batches(setup);
    std::vector<render::Hit> hits;
    for (std::uint64_t c = next++; c < plan.chunks(); c = next++) {
        Clock::duration traced{};
        batches.for_each(plan.first(c), plan.size(c), [&](std::span<const render::Ray> r) {
            hits.resize(r.size());
            const auto t0 = Clock::now();
            setup.renderer.intersect(r, hits);
            traced += Clock::now() - t0;
            rays += r.size();
        });
        seconds[c] = std::chrono::duration<double>(traced).count();
    }
}

}  // namespace

double makespan(const std::vector<double>& seconds, int threads) {
    std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
    for (int i = 0; i < std::max(1, threads); ++i) free_at.push(0.0);
    double end = 0;
    for (const double s : seconds) {
        const double done = free_at.top() + s;
        free_at.pop();
        free_at.push(done);
        end = std::max(end, done);
    }
    return end;
}

Ceiling trace_ceiling(const render::Setup& setup) {
    const render::ChunkPlan plan = render::chunk_plan(setup.sensor, setup.options);
    std::vector<double> seconds(plan.chunks(), 0.0);
    std::atomic<std::uint64_t> next{0}, rays{0};
    std::vector<std::thread> pool;
    for (int i = 0; i < plan.threads; ++i)
        pool.emplace_back(trace_chunks, std::cref(setup), std::cref(plan), std::ref(next),
                          std::ref(rays), std::ref(seconds));
    for (auto& t : pool) t.join();
    return {plan.pulses, rays.load(), makespan(seconds, plan.threads)};
}

}  // namespace mirage::hil
