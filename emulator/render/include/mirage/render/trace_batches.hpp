// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "mirage/core/time.hpp"
#include "mirage/render/renderer.hpp"
#include "mirage/render/setup.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::render {

// Pulses per work unit: `requested` rounded down to whole firing groups (at least one), so the
// ray regrouping never splits a column.
std::size_t chunk_pulses(const sensor::SensorModel& sensor, std::size_t requested);
// Chunks (of `requested` pulses rounded as chunk_pulses() does) that cover `lead` of the
// sensor's firing, at least one.
std::size_t chunks_for_lead(const sensor::SensorModel& sensor, std::size_t requested,
                            core::Nanos lead);

// Pulses traced at once (whole firing groups): rays and hits of one batch stay in cache. A chunk
// is traced in batches of this size from its first pulse.
inline constexpr std::size_t kTraceBatchPulses = 2048;
std::size_t trace_batch_pulses(const sensor::SensorModel& sensor);

// How render() cuts a run into chunks, the unit of work its worker threads take in turn.
struct ChunkPlan {
    std::uint64_t pulses = 0;  // of the whole run
    std::size_t chunk = 1;     // pulses per chunk (chunk_pulses())
    int threads = 1;           // worker threads
    std::uint64_t chunks() const { return (pulses + chunk - 1) / chunk; }
    std::uint64_t first(std::uint64_t c) const { return c * chunk; }
    std::size_t size(std::uint64_t c) const {
        return static_cast<std::size_t>(std::min<std::uint64_t>(chunk, pulses - first(c)));
    }
};
ChunkPlan chunk_plan(const sensor::SensorModel& sensor, const RenderOptions& options);

// The pipeline's own ray generation, for the benchmark's Embree ceiling: the rays render()
// traces for pulses [first, first + n) of a chunk, in its trace batches (same boundaries, same
// order: both go through one function). Holds a batch's buffers: one per thread.
class TraceBatches {
  public:
    explicit TraceBatches(const Setup& setup);  // reads its sensor, trajectory, mount, start
    ~TraceBatches();
    TraceBatches(const TraceBatches&) = delete;
    TraceBatches& operator=(const TraceBatches&) = delete;

    // Builds the batches in order and calls fn(rays) on each; the rays live until it returns.
    void for_each(std::uint64_t first, std::size_t n,
                  const std::function<void(std::span<const Ray>)>& fn);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mirage::render
