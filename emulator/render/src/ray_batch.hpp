// SPDX-License-Identifier: Apache-2.0
// Ray generation: a batch of pulses, their sensor poses and the sub-rays traced for them.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "mirage/core/pose.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/render/renderer.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::render {

class RayBatchBuilder;

// An adaptive footprint's pulse (docs/physics.md §2.9): what its probes found, and for a plane
// the footprint integral over it in closed form.
struct PlaneFootprint {
    enum Kind : std::uint8_t { kSampled, kMissed, kPlane } kind = kSampled;
    double range_m = 0;       // power-weighted mean range
    double power_factor = 0;  // received power over the central ray's
    double sigma_m = 0;       // power-weighted RMS spread of the range
};

// Pulses of one trace batch in firing order, their sensor poses, and the rays traced for them.
struct RayBatch {
    std::uint64_t first = 0;  // global index of the batch's first pulse
    std::vector<sensor::PulseSpec> specs;
    // Per pulse, one array per axis (so the pose loop vectorises), local frame, double: the
    // sensor origin and the nominal beam direction.
    std::array<std::vector<double>, 3> origin, direction;
    std::vector<Ray> rays;                 // tracing order
    std::vector<std::uint32_t> first_ray;  // index in `rays` of pulse i's first sub-ray; the
                                           // S sub-rays of a pulse are adjacent in `rays`
    // The pose loop's inputs, copied out of `specs`: firing time (ns from the start, exact in
    // double) and the sensor-frame direction.
    std::vector<double> t;
    std::array<std::vector<double>, 3> v;
    // Set by PulseShader::trace: the rays it traced and, for an adaptive footprint, each pulse's
    // probes' verdict (empty when sampled); the rest's hits read as misses. part_at is its
    // scratch: the places in `rays` of one pass's rays.
    std::size_t traced = 0;
    std::vector<PlaneFootprint> plane;
    std::vector<std::uint32_t> part_at;
    std::vector<std::uint8_t> block_done;      // per block of sub-rays (tracing order): no rest
    const RayBatchBuilder* builder = nullptr;  // that built it (complete())
    // Set by PulseShader::wander (turbulence), empty otherwise: per pulse, the factor its
    // sub-rays' offsets grow by (the beam's short-term spread) and, with noise, the receiver's
    // axis as the return's image wanders (unit, local frame).
    std::vector<double> spread;
    std::array<std::vector<double>, 3> axis;

    Eigen::Vector3d origin_of(std::size_t i) const {
        return {origin[0][i], origin[1][i], origin[2][i]};
    }
    // Pulse i's footprint was taken in closed form on one plane (adaptive footprints).
    bool planar(std::size_t i) const {
        return !plane.empty() && plane[i].kind == PlaneFootprint::kPlane;
    }
    Eigen::Vector3d direction_of(std::size_t i) const {
        return {direction[0][i], direction[1][i], direction[2][i]};
    }
    double spread_of(std::size_t i) const { return spread.empty() ? 1.0 : spread[i]; }
    // Where the pixel looks for pulse i's light: its beam's nominal direction, or as the image
    // wanders.
    Eigen::Vector3d axis_of(std::size_t i) const {
        if (axis[0].empty()) return direction_of(i);
        return {axis[0][i], axis[1][i], axis[2][i]};
    }
};

// Adaptive footprints' probes among `subrays` hexagonal sub-rays (1 = probe): the central one and
// six on the outer ring 60° apart (for 7, the whole ring).
std::vector<std::uint8_t> footprint_probes(std::size_t subrays);

// Builds the batches every tracer of the pipeline traces: render(), WindowRenderer and the
// benchmark's Embree ceiling (TraceBatches) all go through for_each_batch().
class RayBatchBuilder {
  public:
    RayBatchBuilder(const sensor::SensorModel& sensor, const core::Trajectory& trajectory,
                    const core::Mount& mount, core::GpsTime start);

    const std::vector<sensor::SubRay>& subrays() const { return subrays_; }

    // Pulses [first, first + n) in batches of trace_batch_pulses() counted from `first`, in
    // order: each is built into `g` and handed to fn(g), which may turn its rays (beam wander).
    // The one place where batch boundaries are decided.
    template <class Fn>
    void for_each_batch(std::uint64_t first, std::size_t n, RayBatch& g, Fn&& fn) const {
        for (std::size_t done = 0; done < n; done += batch_) {
            build(first + done, std::min(batch_, n - done), g);
            fn(g);
        }
    }

    // One batch: pulses [first, first + n). An adaptive footprint's pulses get their probes only.
    void build(std::uint64_t first, std::size_t n, RayBatch& g) const;
    // The same pulses' specs, origins and directions only, without rays (coincidence's gates).
    void build_lines(std::uint64_t first, std::size_t n, RayBatch& g) const;
    // The sub-rays other than probes of the block of rays at [r, r + S), around its central ray,
    // their offsets times `spread` (the beam's turbulent spread, RayBatch::spread).
    void complete(RayBatch& g, std::size_t r, double spread = 1.0) const;

  private:
    void load_pulses(std::uint64_t first, std::size_t n, RayBatch& g) const;
    void blend_batch_poses(RayBatch& g) const;
    void make_rays(RayBatch& g) const;
    // Which sub-rays add_subrays() makes: all, or an adaptive footprint's probes, or the others.
    enum class Part { All, Probes, Rest };
    void add_subrays(const Ray& base, const Eigen::Vector3d& d, Ray* out, Part part,
                     float spread = 1.0f) const;

    const sensor::SensorModel& sensor_;
    const core::Trajectory& trajectory_;
    core::Pose mount_;
    core::GpsTime start_;
    std::vector<sensor::SubRay> subrays_;
    std::vector<std::pair<float, float>> tanf_;  // tangents of the sub-ray offsets
    std::vector<float> inv_normf_;
    std::vector<std::uint8_t> probes_;  // adaptive footprints: footprint_probes(), else empty
    std::uint32_t group_;
    std::size_t pose_stride_;  // pulses between exact poses
    std::size_t batch_;        // trace_batch_pulses()
};

}  // namespace mirage::render
