// SPDX-License-Identifier: Apache-2.0
// Scheduling: render() cuts the run into chunks, renders them on worker threads (rays, trace,
// shade, and encoding when the sink can) and writes them in order on the calling thread.
#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "chunk_queue.hpp"
#include "mirage/render/pipeline.hpp"
#include "ray_batch.hpp"
#include "shading.hpp"
#include "stage_clock.hpp"

namespace mirage::render {
namespace {

// What every worker of one render() call shares (read-only but for the queue and the sink's
// thread-safe encode()).
struct Run {
    const RayBatchBuilder& builder;
    const PulseShader& shader;
    PointSink& sink;
    bool encodes;
    ChunkPlan plan;
    ChunkQueue& queue;
};

// A worker's buffers, reused from batch to batch.
struct WorkerBuffers {
    RayBatch g;
    std::vector<Hit> hits;
    ShadeScratch scratch;
};

// Chunk c, traced in batches that keep rays and hits in cache; the chunk (the unit of hand-over
// between threads) spans several, so threads wake less often.
void render_chunk(const Run& run, std::uint64_t c, WorkerBuffers& w, ChunkResult& result) {
    StageClock clock;
    run.shader.begin_chunk(run.plan.first(c), w.scratch);
    run.builder.for_each_batch(run.plan.first(c), run.plan.size(c), w.g, [&](RayBatch& g) {
        clock.lap(StageClock::kRays);
        run.shader.trace(g, w.hits);
        clock.lap(StageClock::kTrace);
        run.shader.shade(g, w.hits, run.builder.subrays(), w.scratch, result.shaded);
        clock.lap(StageClock::kShade);
        if (run.encodes) {
            run.sink.encode_recorded(result.shaded.points, result.shaded.samples, *result.encoded);
            result.shaded.points.clear();
            result.shaded.samples.clear();
            clock.lap(StageClock::kOutput);
        }
    });
    run.shader.end_chunk(run.plan.first(c) + run.plan.size(c), w.scratch);
    clock.add_to(result.shaded.stats);
}

// A worker thread: chunks until none is left or the run ends.
void work(const Run& run) {
    pthread_setname_np(pthread_self(), "mirage-render");  // for top, perf and ps
    WorkerBuffers w;
    std::uint64_t c = 0;
    while (run.queue.take(c)) {
        std::unique_ptr<ChunkResult> result;
        try {
            result = run.queue.result();
            if (run.encodes && !result->encoded) result->encoded = run.sink.new_encoded();
            render_chunk(run, c, w, *result);
        } catch (...) {
            run.queue.fail(std::current_exception());
            run.shader.abort_chunks();
            return;
        }
        run.queue.put(c, std::move(result));
    }
}

// Hands one chunk to the sink (on the calling thread); `next_pulse` follows its last pulse.
void write_chunk(const Run& run, ChunkResult& ready, std::uint64_t next_pulse, RenderStats& stats) {
    const double c0 = thread_cpu_s();
    if (run.encodes)
        run.sink.write_encoded(*ready.encoded);
    else
        run.sink.write_recorded(ready.shaded.points, ready.shaded.samples);
    run.sink.pulses_done(next_pulse);
    stats.cpu_output_s += thread_cpu_s() - c0;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The calling thread: writes the chunks in order as they are ready.
RenderStats write_in_order(const Run& run, const ProgressFn& progress,
                           std::chrono::steady_clock::time_point t0) {
    RenderStats stats;
    for (std::uint64_t written = 1;; ++written) {
        std::unique_ptr<ChunkResult> ready = run.queue.next();
        if (!ready) break;
        try {
            write_chunk(run, *ready,
                        std::min<std::uint64_t>(written * run.plan.chunk, run.plan.pulses), stats);
        } catch (...) {
            run.queue.fail(std::current_exception());
            break;
        }
        stats.add(ready->shaded.stats);
        run.queue.recycle(std::move(ready));
        if (progress) {
            stats.seconds = seconds_since(t0);
            progress(stats);
        }
    }
    return stats;
}

}  // namespace

std::size_t chunk_pulses(const sensor::SensorModel& sensor, std::size_t requested) {
    const std::size_t group = std::max<std::uint32_t>(1, sensor.scan->group_size());
    return std::max<std::size_t>(group, requested / group * group);
}

std::size_t chunks_for_lead(const sensor::SensorModel& sensor, std::size_t requested,
                            core::Nanos lead) {
    const std::uint64_t pulses = sensor.scan->pulse_count(lead);
    const std::uint64_t c = chunk_pulses(sensor, requested);  // ≥ 1: one firing group at least
    return static_cast<std::size_t>(std::max<std::uint64_t>(1, (pulses + c - 1) / c));
}

ChunkPlan chunk_plan(const sensor::SensorModel& sensor, const RenderOptions& options) {
    ChunkPlan plan;
    plan.pulses = sensor.scan->pulse_count(options.duration);
    plan.chunk = chunk_pulses(sensor, options.chunk_pulses);
    plan.threads = options.threads > 0
                       ? options.threads
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return plan;
}

RenderStats render(const Setup& setup, PointSink& sink, const ProgressFn& progress,
                   const std::atomic<bool>* stop) {
    const auto t0 = std::chrono::steady_clock::now();
    const RenderOptions& opt = setup.options;
    const ChunkPlan plan = chunk_plan(setup.sensor, opt);
    const RayBatchBuilder builder(setup.sensor, setup.trajectory, setup.mount, opt.start);
    const PulseShader shader(setup);
    const std::uint64_t window = opt.window_chunks > 0
                                     ? opt.window_chunks
                                     : static_cast<std::uint64_t>(plan.threads) * 2 + 2;
    ChunkQueue queue(plan.chunks(), window, stop);
    const Run run{builder, shader, sink, sink.new_encoded() != nullptr, plan, queue};

    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(plan.threads));
    for (int i = 0; i < plan.threads; ++i) pool.emplace_back(work, std::cref(run));
    RenderStats stats = write_in_order(run, progress, t0);
    queue.close();
    for (auto& t : pool) t.join();
    queue.rethrow();
    const double c0 = thread_cpu_s();
    sink.finish();  // the one place a render's chain of stages ends
    stats.cpu_output_s += thread_cpu_s() - c0;
    stats.seconds = seconds_since(t0);
    return stats;
}

}  // namespace mirage::render
