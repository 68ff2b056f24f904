// SPDX-License-Identifier: Apache-2.0
// The pipeline: pose at each pulse's firing time -> sub-rays -> Renderer -> physics -> points.
#pragma once
#include <atomic>
#include <functional>

#include "mirage/render/point_sink.hpp"
#include "mirage/render/render_stats.hpp"
#include "mirage/render/setup.hpp"
#include "mirage/render/trace_batches.hpp"
#include "mirage/render/window_renderer.hpp"

namespace mirage::render {

// Progress: pulses done so far (called from the writer thread, rate-limited by the caller).
using ProgressFn = std::function<void(const RenderStats&)>;

// Renders setup.options.duration of pulses on worker threads into `sink`, in pulse order, then
// finishes the sink (PointSink::finish). Stops early (returns what was written, and finishes the
// sink) when `stop` becomes true (SIGINT). A failure (a worker's or the sink's) is rethrown
// without finishing the sink.
RenderStats render(const Setup& setup, PointSink& sink, const ProgressFn& progress = {},
                   const std::atomic<bool>* stop = nullptr);

}  // namespace mirage::render
