// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>

#include "mirage/core/pose.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/physics/radiometry.hpp"
#include "mirage/render/renderer.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::render {

struct RenderOptions {
    std::uint64_t seed = 1;
    int threads = 0;        // 0 = hardware concurrency
    core::GpsTime start{};  // time of pulse 0
    core::Nanos duration{std::chrono::seconds(1)};
    bool noise = true;  // range noise, jitter, detector noise
    // Work unit handed between threads; results do not depend on it.
    std::size_t chunk_pulses = 32768;
    // Chunks the workers may finish ahead of the one being written (0: 2 per thread + 2). A
    // real-time output raises it so the renderers' lead rides out tens of milliseconds of CPU
    // contention. Results do not depend on it either.
    std::size_t window_chunks = 0;
    physics::IntensityCalibration intensity;
    // Digitised samples recorded per pulse with returns (linear detector only; 0: none), from
    // the first sample of its first echo's arrivals (docs/time-resolved.md §13).
    std::uint32_t waveform_samples = 0;
};

// What a render needs besides its output: render(), WindowRenderer and TraceBatches take it. The
// scene, renderer, sensor and trajectory are referred to and must outlive whatever uses the
// Setup; the mount, environment and options are values (copied with it).
struct Setup {
    const scene::Scene& scene;
    const Renderer& renderer;
    const sensor::SensorModel& sensor;
    const core::Trajectory& trajectory;
    core::Mount mount;
    physics::Environment env;
    RenderOptions options;
};

}  // namespace mirage::render
