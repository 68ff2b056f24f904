// SPDX-License-Identifier: Apache-2.0
// Scheduling: the ordered hand-over of chunks between render() workers and its writing thread.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <vector>

#include "mirage/render/point_sink.hpp"
#include "shading.hpp"

namespace mirage::render {

// One chunk's output on its way from a worker to the writer.
struct ChunkResult {
    ShadedPoints shaded;                     // when the sink encodes: one batch's at a time
    std::unique_ptr<EncodedPoints> encoded;  // the chunk's, when the sink encodes
};

// Workers take chunk numbers and put their results in any order; the writer takes them in chunk
// order, so the output is identical for any thread count. At most `window` chunks are in flight.
// Written results go back to a pool: fresh multi-megabyte vectors per chunk cost more in page
// faults than the physics.
class ChunkQueue {
  public:
    ChunkQueue(std::uint64_t chunks, std::uint64_t window, const std::atomic<bool>* stop);

    // Worker: the next chunk to render (waits for room in the window); false when there is none
    // left or the run is ending (stopped, failed or closed).
    bool take(std::uint64_t& c);
    // Worker: an empty result to fill, recycled when one is free.
    std::unique_ptr<ChunkResult> result();
    void put(std::uint64_t c, std::unique_ptr<ChunkResult> r);

    // Writer: the next result in chunk order; null once all are written, or when the run ended
    // and the next one is not ready.
    std::unique_ptr<ChunkResult> next();
    void recycle(std::unique_ptr<ChunkResult> r);

    // Either side: keeps the first error and ends the run.
    void fail(std::exception_ptr e);
    // Writer, at the end: workers return from take().
    void close();
    // The first error, if any.
    void rethrow() const;

  private:
    const std::uint64_t chunks_, window_;
    const std::atomic<bool>* stop_;
    std::mutex mu_;
    std::condition_variable cv_done_, cv_space_;
    std::deque<std::unique_ptr<ChunkResult>> slots_;  // slots_[k] = chunk written_ + k
    std::vector<std::unique_ptr<ChunkResult>> pool_free_;
    std::uint64_t written_ = 0, next_ = 0;
    bool abort_ = false;
    std::exception_ptr error_;
};

}  // namespace mirage::render
