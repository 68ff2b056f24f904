// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mirage::hil {

struct ThroughputRow {
    std::string sensor;
    int sub_rays = 1;
    std::uint64_t pulses = 0, points = 0;
    double real_pulse_rate = 0;
    double pipeline_pulses_per_s = 0, pipeline_points_per_s = 0;
    double ceiling_pulses_per_s = 0, ceiling_rays_per_s = 0;
    // Pipeline and ceiling are each the best of `repeats` interleaved runs (the least disturbed
    // by other load on the machine); the ratio of each run's pair spans [ratio_min, ratio_max].
    int repeats = 1;
    double ratio_min = 0, ratio_max = 0;
    double ratio() const {
        return ceiling_pulses_per_s > 0 ? pipeline_pulses_per_s / ceiling_pulses_per_s : 0;
    }
    double x_real_time() const {
        return real_pulse_rate > 0 ? pipeline_pulses_per_s / real_pulse_rate : 0;
    }
};

// The linear-mode (waveform) detector against the discrete one on the same rays and against the
// same-run ceiling: each the best of `repeats` interleaved runs.
struct DetectorRow {
    std::string sensor;
    int sub_rays = 19;
    std::uint64_t pulses = 0;
    int repeats = 1;
    double discrete_pulses_per_s = 0, waveform_pulses_per_s = 0, ceiling_pulses_per_s = 0;
    double waveform_points_per_s = 0, discrete_points_per_s = 0;
    // The waveform detector with constant-fraction timing and with Gaussian decomposition
    // (waveform_pulses_per_s: peak timing).
    double cfd_pulses_per_s = 0, decomposition_pulses_per_s = 0;
    double cfd_to_peak() const {
        return waveform_pulses_per_s > 0 ? cfd_pulses_per_s / waveform_pulses_per_s : 0;
    }
    double decomposition_to_peak() const {
        return waveform_pulses_per_s > 0 ? decomposition_pulses_per_s / waveform_pulses_per_s : 0;
    }
    double to_discrete() const {
        return discrete_pulses_per_s > 0 ? waveform_pulses_per_s / discrete_pulses_per_s : 0;
    }
    double to_ceiling() const {
        return ceiling_pulses_per_s > 0 ? waveform_pulses_per_s / ceiling_pulses_per_s : 0;
    }
};

// One sensor at one path depth (docs/time-resolved.md §5) on the demo town, whose crowns and
// glass front continue paths; depth 1 is the first-hit pipeline on the same rays.
struct PathRow {
    std::string sensor;
    int sub_rays = 7;
    int depth = 1;
    std::uint64_t pulses = 0;
    int repeats = 1;
    double pulses_per_s = 0, points_per_s = 0, ceiling_pulses_per_s = 0;
    double segments_per_pulse = 0;      // continuation segments traced per pulse
    double first_hit_pulses_per_s = 0;  // the same sensor's depth-1 row
    double to_ceiling() const {
        return ceiling_pulses_per_s > 0 ? pulses_per_s / ceiling_pulses_per_s : 0;
    }
    double to_first_hit() const {
        return first_hit_pulses_per_s > 0 ? pulses_per_s / first_hit_pulses_per_s : 0;
    }
};

// Error of a render against a denser reference (same BVH: its quality never changes a hit).
struct ErrorRow {
    std::string detector = "discrete";  // or "waveform" (the linear detector, peak timing)
    std::string footprint = "sampled";  // or "adaptive" (beam.footprint)
    int sub_rays = 1;
    int reference_sub_rays = 37;
    double seconds = 0, reference_seconds = 0;
    double range_rms_m = 0, range_p50_m = 0, range_p95_m = 0, intensity_rms = 0,
           presence_mismatch = 0;
    // Pulses whose return lies over c·τ/2 from the reference's (the strongest surface flipped),
    // as a fraction of those with a return in both, and the range RMS over the others.
    double other_surface = 0, same_surface_range_rms_m = 0;
};

// A photon-counting array over the demo town (docs/photon-counting.md §7): the Geiger-mode
// pipeline against the ceiling of the same rays, its real-time factor, and the coincidence
// processor's time for the collection.
struct PhotonRow {
    std::string sensor, trajectory;
    std::uint64_t pulses = 0, points = 0, coincidence_points = 0;  // pixel-pulses, events
    int repeats = 1;
    double pulses_per_s = 0, points_per_s = 0, ceiling_pulses_per_s = 0;
    double real_pulse_rate = 0;  // pixel-pulses per second of the sensor
    double collection_seconds = 0, coincidence_seconds = 0;
    double to_ceiling() const {
        return ceiling_pulses_per_s > 0 ? pulses_per_s / ceiling_pulses_per_s : 0;
    }
    double x_real_time() const { return real_pulse_rate > 0 ? pulses_per_s / real_pulse_rate : 0; }
    double coincidence_x_real_time() const {
        return coincidence_seconds > 0 ? collection_seconds / coincidence_seconds : 0;
    }
};

// A BVH quality: build time and memory, and the render time of one job with it.
struct BvhRow {
    std::string quality;
    int sub_rays = 19;
    double build_seconds = 0, render_seconds = 0;
    std::uint64_t bvh_bytes = 0, rays = 0;
};

struct BenchReport {
    std::string machine;
    double scene_seconds = 0, bvh_build_seconds = 0;
    std::uint64_t triangles_placed = 0, unique_triangles = 0, bvh_bytes = 0;
    std::vector<ThroughputRow> throughput;
    std::vector<DetectorRow> detectors;
    std::vector<PathRow> paths;
    std::vector<PhotonRow> photon;
    double las_points_per_s = 0, las_mb_per_s = 0;
    std::uint64_t las_points = 0;
    std::vector<ErrorRow> errors;
    std::vector<BvhRow> bvh;
};

// A row whose best pipeline run beats its best ceiling run by more than this is a broken
// measurement: the ceiling traces exactly the pipeline's rays and does nothing else.
inline constexpr double kCeilingTolerance = 1.1;
// The rows above the ceiling: pipeline/ceiling over kCeilingTolerance, or not a number.
std::vector<ThroughputRow> rows_above_ceiling(const BenchReport& r);

// The CPU's model name from /proc/cpuinfo ("unknown CPU" when absent).
std::string cpu_model();
// CPU model, cores, threads used, Embree version.
std::string machine_description(int threads);
// report.md, report.json and time_vs_error.svg in `dir`. A figure that is not finite reads n/a
// in the markdown, null in the JSON, and is left out of the plot.
void write_reports(const BenchReport& r, const std::string& dir);
// The JSON report (report.json).
std::string report_json(const BenchReport& r);

}  // namespace mirage::hil
