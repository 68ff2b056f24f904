// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "mirage/core/point.hpp"
#include "mirage/core/pose.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/physics/radiometry.hpp"
#include "mirage/render/renderer.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::render {

// A chunk of points a sink has encoded on a render worker: the sink's own type, see
// PointSink::new_encoded.
class EncodedPoints {
  public:
    virtual ~EncodedPoints() = default;
    virtual void clear() = 0;  // empty, keeping capacity: reused for later chunks
};

// Receives points in pulse order (deterministic whatever the thread count), one chunk at a time,
// from a single thread at a time.
class PointSink {
  public:
    virtual ~PointSink() = default;
    virtual void write(std::span<const core::PointRecord> points) = 0;
    // Called after each chunk's write: every pulse before `next_pulse` has been delivered. Packet
    // encoders need it because pulses without returns produce no points but still fill packets.
    virtual void pulses_done(std::uint64_t next_pulse) { (void)next_pulse; }

    // Optional encoding on the render workers. A sink that returns a buffer here has each trace
    // batch's points passed to encode() on the worker that made them, while they are in cache
    // and in parallel, and then receives whole chunks, in order, through write_encoded() instead
    // of write(). new_encoded() and encode() are called from several threads at once.
    virtual std::unique_ptr<EncodedPoints> new_encoded() const { return nullptr; }
    virtual void encode(std::span<const core::PointRecord> points, EncodedPoints& out) const {
        (void)points;
        (void)out;
    }
    virtual void write_encoded(EncodedPoints& chunk) { (void)chunk; }
};

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
};

struct RenderStats {
    std::uint64_t pulses = 0;
    std::uint64_t points = 0;
    std::uint64_t misses = 0;     // no geometry within max range
    std::uint64_t voids = 0;      // hit but N_laser < γ·ΔN
    std::uint64_t too_close = 0;  // hit nearer than min range
    std::uint64_t rays = 0;       // sub-rays traced
    double seconds = 0;
    // CPU time per stage summed over threads (each worker's CPU clock per chunk, split between the
    // stages by the steady clock): where the time goes, independent of other processes.
    double cpu_rays_s = 0;    // pulse specs, poses, ray generation
    double cpu_trace_s = 0;   // Renderer::intersect
    double cpu_shade_s = 0;   // physics, noise, point records
    double cpu_output_s = 0;  // the sink: encoding (on the workers when it can) and writing

    // Adds the counts and CPU times of `s` (not its seconds).
    void add(const RenderStats& s) {
        cpu_rays_s += s.cpu_rays_s;
        cpu_trace_s += s.cpu_trace_s;
        cpu_shade_s += s.cpu_shade_s;
        cpu_output_s += s.cpu_output_s;
        pulses += s.pulses;
        points += s.points;
        misses += s.misses;
        voids += s.voids;
        too_close += s.too_close;
        rays += s.rays;
    }
};

// Progress: pulses done so far (called from the writer thread, rate-limited by the caller).
using ProgressFn = std::function<void(const RenderStats&)>;

// The spine: pose at each pulse's firing time → sub-rays → Embree → physics → points.
// Stops early (returns what was written) when `stop` becomes true (SIGINT).
RenderStats render(const scene::Scene& scene, const Renderer& renderer,
                   const sensor::SensorModel& sensor, const core::Trajectory& trajectory,
                   const core::Mount& mount, const physics::Environment& env,
                   const RenderOptions& opt, PointSink& sink, const ProgressFn& progress = {},
                   const std::atomic<bool>* stop = nullptr);

// Renders a few pulses at a time on the calling thread, for live emulation: a packet's worth of
// pulses just in time, with the poses an INS has reported by then. Same physics and per-pulse
// randomness as render(), so its points equal render()'s for the same pulses and poses. The scene,
// renderer and sensor must outlive it; the mount, environment and options are copied.
class WindowRenderer {
  public:
    WindowRenderer(const scene::Scene& scene, const Renderer& renderer,
                   const sensor::SensorModel& sensor, const core::Mount& mount,
                   const physics::Environment& env, const RenderOptions& opt);
    ~WindowRenderer();
    WindowRenderer(const WindowRenderer&) = delete;
    WindowRenderer& operator=(const WindowRenderer&) = delete;

    // Appends the points of pulses [first, first + n) (times from opt.start) to `out`, with
    // poses from `trajectory`; adds to `stats`.
    void render(const core::Trajectory& trajectory, std::uint64_t first, std::size_t n,
                std::vector<core::PointRecord>& out, RenderStats& stats);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mirage::render

namespace mirage::render {

// Pulses per work unit: `requested` rounded down to whole firing groups (at least one), so the
// ray regrouping never splits a column. The benchmark's ceiling uses the same chunks.
std::size_t chunk_pulses(const sensor::SensorModel& sensor, std::size_t requested);
// Chunks (of `requested` pulses rounded as chunk_pulses() does) that cover `lead` of the
// sensor's firing, at least one.
std::size_t chunks_for_lead(const sensor::SensorModel& sensor, std::size_t requested,
                            core::Nanos lead);

// Pulses traced at once (whole firing groups): rays and hits of one batch stay in cache. A chunk
// is traced in batches of this size from its first pulse.
inline constexpr std::size_t kTraceBatchPulses = 2048;
std::size_t trace_batch_pulses(const sensor::SensorModel& sensor);

// The rays the pipeline traces for pulses [first, first + n), in its tracing order (one channel
// over neighbouring firing groups, sub-rays adjacent). Used by the benchmark to time the bare
// Embree ceiling on exactly the pipeline's rays.
std::vector<Ray> pipeline_rays(const sensor::SensorModel& sensor,
                               const core::Trajectory& trajectory, const core::Mount& mount,
                               core::GpsTime start, std::uint64_t first, std::size_t n);

}  // namespace mirage::render
