// SPDX-License-Identifier: Apache-2.0
// `mirage bench`: throughput of the whole pipeline against the bare Embree ceiling on the same
// rays, BVH build and memory, LAS write rate, and run time against error.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <span>
#include <thread>
#include <vector>

#include "bench_error.hpp"
#include "bench_report.hpp"
#include "ceiling.hpp"
#include "commands.hpp"
#include "job.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/render/coincidence.hpp"

namespace mirage::hil {
namespace {

using Clock = std::chrono::steady_clock;

struct Opts {
    std::string out_dir = "bench-results";
    int threads = 0;
    std::string seconds = "20";  // simulated seconds per throughput configuration (warm-up < 3 %)
    bool quick = false;
    std::vector<std::string> sensors;  // empty: all
    std::vector<int> sub_rays;         // empty: 1, 7, 19
    bool throughput_only = false;
    int repeat = 3;  // pipeline/ceiling pairs per row (--quick: 1 unless given)
    bool repeat_given = false;
};

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

render::RenderStats run_pipeline_to_null(const Job& job) {
    las::LasWriter writer("/dev/null", job.scene->georef);
    las::LasSink sink(writer);
    return render::render(job.setup(), sink);
}

// One pipeline/ceiling pair (the k-th) into the row: the best of each and the pair's ratio.
void add_pair(ThroughputRow& row, int k, const Ceiling& ceiling, const render::RenderStats& run) {
    const double pipeline_pulses = double(run.pulses) / run.seconds;
    const double pair = ceiling.pulses_per_s() > 0 ? pipeline_pulses / ceiling.pulses_per_s() : 0.0;
    row.ratio_min = k == 0 ? pair : std::min(row.ratio_min, pair);
    row.ratio_max = k == 0 ? pair : std::max(row.ratio_max, pair);
    if (ceiling.pulses_per_s() > row.ceiling_pulses_per_s) {
        row.ceiling_pulses_per_s = ceiling.pulses_per_s();
        row.ceiling_rays_per_s = ceiling.rays_per_s();
    }
    if (pipeline_pulses > row.pipeline_pulses_per_s) {
        row.pipeline_pulses_per_s = pipeline_pulses;
        row.pipeline_points_per_s = double(run.points) / run.seconds;
        row.points = run.points;
    }
}

// The job of one benchmark row: the shared town and BVH, this sensor, trajectory and sub-rays.
Job row_job(const BenchBase& base, const Job& shared, const char* sensor, const char* trajectory,
            int sub_rays, const Opts& o) {
    JobInputs in = base.inputs;
    in.sensor = sensor;
    in.trajectory = trajectory;
    in.duration = o.quick ? "0.05" : o.seconds;
    in.sub_rays = sub_rays;
    Job job = load_job_with_scene(in, base.town, base.scene_seconds, false);
    job.renderer = shared.renderer;
    return job;
}

// One sensor and sub-ray count. Pipeline and ceiling alternate, so a stretch of load from
// elsewhere on the machine disturbs one run of each kind, not all runs of one kind.
ThroughputRow throughput_row(const BenchBase& base, const Job& shared, const char* sensor,
                             const char* trajectory, int sub_rays, const Opts& o) {
    Job job = row_job(base, shared, sensor, trajectory, sub_rays, o);
    ThroughputRow row;
    row.sensor = sensor;
    row.sub_rays = sub_rays;
    row.pulses = job.sensor.scan->pulse_count(job.options.duration);
    row.real_pulse_rate = job.sensor.scan->pulse_rate_hz();
    row.repeats = o.quick && !o.repeat_given ? 1 : o.repeat;
    // The pipeline first in each pair: the first run of a row meets the parts of the BVH its
    // sensor sees cold, which in a short run slowed the ceiling several times over.
    for (int k = 0; k < row.repeats; ++k) {
        const render::RenderStats run = run_pipeline_to_null(job);
        add_pair(row, k, trace_ceiling(job.setup()), run);
    }
    fmt::print(
        "{:>11} sub-rays {:>2}: pipeline {:6.2f} M pulses/s ({:6.2f} M points/s) | ceiling "
        "{:6.2f} M pulses/s ({:6.1f} M rays/s) | ratio {:.2f} (pairs {:.2f}–{:.2f}, {} runs) | "
        "{:6.1f}x real time\n",
        sensor, sub_rays, row.pipeline_pulses_per_s / 1e6, row.pipeline_points_per_s / 1e6,
        row.ceiling_pulses_per_s / 1e6, row.ceiling_rays_per_s / 1e6, row.ratio(), row.ratio_min,
        row.ratio_max, row.repeats, row.x_real_time());
    return row;
}

void bench_throughput(const BenchBase& base, const Job& shared, const Opts& o,
                      BenchReport& report) {
    struct Config {
        const char* sensor;
        const char* trajectory;
    };
    const Config configs[] = {
        {"vlp16", "demo-car"}, {"hdl64e-s3", "demo-car"}, {"als-mirror", "demo-flight"}};
    const std::vector<int> sub_rays = o.sub_rays.empty() ? std::vector<int>{1, 7, 19} : o.sub_rays;
    for (const auto& c : configs) {
        if (!o.sensors.empty() &&
            std::find(o.sensors.begin(), o.sensors.end(), c.sensor) == o.sensors.end())
            continue;
        for (int s : sub_rays) {
            if (o.quick && s == 19 && o.sub_rays.empty()) continue;
            report.throughput.push_back(throughput_row(base, shared, c.sensor, c.trajectory, s, o));
        }
    }
}

// One sensor's detectors on the same job: discrete, waveform (timed by peak, constant fraction
// and decomposition) and the ceiling, interleaved.
DetectorRow detector_row(const BenchBase& base, const Job& shared, const char* sensor,
                         const char* trajectory, int sub_rays, const Opts& o) {
    Job job = row_job(base, shared, sensor, trajectory, sub_rays, o);
    DetectorRow row;
    row.sensor = sensor;
    row.sub_rays = sub_rays;
    row.pulses = job.sensor.scan->pulse_count(job.options.duration);
    row.repeats = o.quick && !o.repeat_given ? 1 : o.repeat;
    const auto rate = [](const render::RenderStats& s, bool points) {
        return double(points ? s.points : s.pulses) / s.seconds;
    };
    for (int k = 0; k < row.repeats; ++k) {
        job.sensor.detector = sensor::DetectorKind::Discrete;
        const render::RenderStats d = run_pipeline_to_null(job);
        job.sensor.detector = sensor::DetectorKind::Linear;
        job.sensor.linear.timing = sensor::EchoTiming::Peak;
        const render::RenderStats w = run_pipeline_to_null(job);
        job.sensor.linear.timing = sensor::EchoTiming::ConstantFraction;
        row.cfd_pulses_per_s =
            std::max(row.cfd_pulses_per_s, rate(run_pipeline_to_null(job), false));
        job.sensor.linear.timing = sensor::EchoTiming::Decomposition;
        row.decomposition_pulses_per_s =
            std::max(row.decomposition_pulses_per_s, rate(run_pipeline_to_null(job), false));
        row.discrete_pulses_per_s = std::max(row.discrete_pulses_per_s, rate(d, false));
        row.discrete_points_per_s = std::max(row.discrete_points_per_s, rate(d, true));
        row.waveform_pulses_per_s = std::max(row.waveform_pulses_per_s, rate(w, false));
        row.waveform_points_per_s = std::max(row.waveform_points_per_s, rate(w, true));
        row.ceiling_pulses_per_s =
            std::max(row.ceiling_pulses_per_s, trace_ceiling(job.setup()).pulses_per_s());
    }
    fmt::print(
        "{:>11} sub-rays {:>2}: waveform {:6.3f} M pulses/s | discrete {:6.3f} | ratio {:.2f} | "
        "ceiling {:6.3f}, waveform/ceiling {:.2f} | constant fraction/peak {:.2f}, "
        "decomposition/peak {:.2f}\n",
        sensor, sub_rays, row.waveform_pulses_per_s / 1e6, row.discrete_pulses_per_s / 1e6,
        row.to_discrete(), row.ceiling_pulses_per_s / 1e6, row.to_ceiling(), row.cfd_to_peak(),
        row.decomposition_to_peak());
    return row;
}

// The waveform detector's rows (docs/time-resolved.md §12): 19 sub-rays (--quick: 7).
void bench_detectors(const BenchBase& base, const Job& shared, const Opts& o, BenchReport& report) {
    const int sub_rays = o.quick ? 7 : 19;
    for (auto [sensor, trajectory] :
         {std::pair{"vlp16", "demo-car"}, {"als-mirror", "demo-flight"}}) {
        if (!o.sensors.empty() &&
            std::find(o.sensors.begin(), o.sensors.end(), sensor) == o.sensors.end())
            continue;
        report.detectors.push_back(detector_row(base, shared, sensor, trajectory, sub_rays, o));
    }
}

// One sensor at path depths 1–3 on the same job, interleaved with the first-hit ceiling.
std::vector<PathRow> path_rows(const BenchBase& base, const Job& shared, const char* sensor,
                               const char* trajectory, int sub_rays, const Opts& o) {
    Job job = row_job(base, shared, sensor, trajectory, sub_rays, o);
    std::vector<PathRow> rows(3);
    const int repeats = o.quick && !o.repeat_given ? 1 : o.repeat;
    double ceiling = 0;
    for (int k = 0; k < repeats; ++k) {
        for (int d = 1; d <= 3; ++d) {
            job.sensor.receiver.max_path_depth = d;
            const render::RenderStats s = run_pipeline_to_null(job);
            PathRow& row = rows[static_cast<std::size_t>(d - 1)];
            const double rate = double(s.pulses) / s.seconds;
            if (rate > row.pulses_per_s) {
                row.pulses_per_s = rate;
                row.points_per_s = double(s.points) / s.seconds;
            }
            row.segments_per_pulse =
                double(s.path_segments) / double(std::max<std::uint64_t>(1, s.pulses));
        }
        ceiling = std::max(ceiling, trace_ceiling(job.setup()).pulses_per_s());
    }
    for (int d = 1; d <= 3; ++d) {
        PathRow& row = rows[static_cast<std::size_t>(d - 1)];
        row.sensor = sensor;
        row.sub_rays = sub_rays;
        row.depth = d;
        row.pulses = job.sensor.scan->pulse_count(job.options.duration);
        row.repeats = repeats;
        row.ceiling_pulses_per_s = ceiling;
        row.first_hit_pulses_per_s = rows[0].pulses_per_s;
        fmt::print(
            "{:>11} sub-rays {:>2} depth {}: {:6.3f} M pulses/s | / depth 1 {:.2f} | / ceiling "
            "{:.2f} | {:.4f} segments per pulse\n",
            sensor, sub_rays, d, row.pulses_per_s / 1e6, row.to_first_hit(), row.to_ceiling(),
            row.segments_per_pulse);
    }
    return rows;
}

// The path-depth rows: 7 sub-rays, the car and the flight over the demo town.
void bench_paths(const BenchBase& base, const Job& shared, const Opts& o, BenchReport& report) {
    for (auto [sensor, trajectory] :
         {std::pair{"vlp16", "demo-car"}, {"als-mirror", "demo-flight"}}) {
        if (!o.sensors.empty() &&
            std::find(o.sensors.begin(), o.sensors.end(), sensor) == o.sensors.end())
            continue;
        for (PathRow& r : path_rows(base, shared, sensor, trajectory, 7, o))
            report.paths.push_back(std::move(r));
    }
}

// The Geiger-mode array at night from a 1 200 m hover over the town (its gate's range): the
// pipeline into /dev/null and the ceiling of its rays, interleaved; then the coincidence processor
// over one run's events, timed against the collection's duration.
PhotonRow photon_row(const BenchBase& base, const Job& shared, const Opts& o) {
    JobInputs in = base.inputs;
    in.sensor = "gmapd-32x32";
    in.trajectory = "static:0,0,1200";
    in.duration = o.quick ? "0.005" : "0.1";
    in.sun_elevation_deg = -1;
    Job job = load_job_with_scene(in, base.town, base.scene_seconds, false);
    job.renderer = shared.renderer;
    PhotonRow row;
    row.sensor = in.sensor;
    row.trajectory = in.trajectory + " at night";
    row.pulses = job.sensor.scan->pulse_count(job.options.duration);
    row.real_pulse_rate = job.sensor.scan->pulse_rate_hz();
    row.collection_seconds = std::chrono::duration<double>(job.options.duration).count();
    row.repeats = o.quick && !o.repeat_given ? 1 : o.repeat;
    for (int k = 0; k < row.repeats; ++k) {
        const render::RenderStats run = run_pipeline_to_null(job);
        if (double(run.pulses) / run.seconds > row.pulses_per_s) {
            row.pulses_per_s = double(run.pulses) / run.seconds;
            row.points_per_s = double(run.points) / run.seconds;
            row.points = run.points;
        }
        row.ceiling_pulses_per_s =
            std::max(row.ceiling_pulses_per_s, trace_ceiling(job.setup()).pulses_per_s());
    }
    render::FirstEventSink events;
    render::render(job.setup(), events);
    const auto t0 = Clock::now();
    render::CoincidenceStats st;
    render::coincidence(job.setup(), events.events, {}, &st);
    row.coincidence_seconds = seconds_since(t0);
    row.coincidence_points = st.points;
    fmt::print(
        "{:>11} photon counting: {:6.3f} M pixel-pulses/s ({:6.3f} M events/s) | ceiling "
        "{:6.3f} | ratio {:.2f} | {:.3f}x real time | coincidence {:.3f} s for {:.3f} s "
        "({:.2f}x real time, {} points)\n",
        row.sensor, row.pulses_per_s / 1e6, row.points_per_s / 1e6, row.ceiling_pulses_per_s / 1e6,
        row.to_ceiling(), row.x_real_time(), row.coincidence_seconds, row.collection_seconds,
        row.coincidence_x_real_time(), row.coincidence_points);
    return row;
}

// LAS write rate to a real file.
void bench_las_rate(const Job& shared, const Opts& o, BenchReport& report) {
    const std::uint64_t n = o.quick ? 500'000 : 5'000'000;
    std::vector<core::PointRecord> pts(65536);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        pts[i].x = double(i % 1000);
        pts[i].y = double(i / 1000);
        pts[i].z = 1.5;
        pts[i].intensity = static_cast<std::uint16_t>(i);
    }
    const auto path = (std::filesystem::path(o.out_dir) / "las_rate.las").string();
    const auto t0 = Clock::now();
    {
        las::LasWriter w(path, shared.scene->georef);
        for (std::uint64_t done = 0; done < n; done += pts.size()) w.write(pts);
        w.close();
    }
    const double secs = seconds_since(t0);
    report.las_points = (n + pts.size() - 1) / pts.size() * pts.size();
    report.las_points_per_s = double(report.las_points) / secs;
    report.las_mb_per_s = double(std::filesystem::file_size(path)) / secs / 1e6;
    std::filesystem::remove(path);
    fmt::print("LAS write (format 6, to a file): {:.2f} M points/s, {:.0f} MB/s\n",
               report.las_points_per_s / 1e6, report.las_mb_per_s);
}

// The scene and BVH, once: their figures into the report.
Job load_shared(BenchBase& base, BenchReport& report) {
    base.town = load_scene_timed("demo", base.scene_seconds);
    report.scene_seconds = base.scene_seconds;
    report.triangles_placed = base.town->placed_triangle_count();
    Job shared = load_job_with_scene(base.inputs, base.town, base.scene_seconds);
    const auto& bs = shared.renderer->build_stats();
    report.bvh_build_seconds = bs.build_seconds;
    report.bvh_bytes = bs.bvh_bytes;
    report.unique_triangles = bs.triangles;
    fmt::print(
        "demo town: {} placed / {} stored triangles, scene {:.2f} s, BVH {:.3f} s, {:.1f} MB "
        "({:.1f} B per stored triangle)\n",
        bs.placed_triangles, bs.triangles, base.scene_seconds, bs.build_seconds,
        double(bs.bvh_bytes) / 1e6,
        double(bs.bvh_bytes) / double(std::max<std::uint64_t>(1, bs.triangles)));
    return shared;
}

// The verdict: exit 1 naming every row whose pipeline beat its ceiling beyond the tolerance.
void check_ceiling(const BenchReport& report) {
    const auto above = rows_above_ceiling(report);
    for (const auto& t : above)
        fmt::print(stderr, "mirage bench: {} with {} sub-rays: pipeline/ceiling {:.2f} > {:.1f}\n",
                   t.sensor, t.sub_rays, t.ratio(), kCeilingTolerance);
    if (!above.empty()) throw CLI::RuntimeError(1);
}

void run_bench(const Opts& o) {
    const int threads =
        o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency());
    std::filesystem::create_directories(o.out_dir);
    BenchReport report;
    report.machine = machine_description(threads);
    BenchBase base;
    base.inputs.scene = "demo";
    base.inputs.threads = threads;
    const Job shared = load_shared(base, report);
    bench_throughput(base, shared, o, report);
    bench_detectors(base, shared, o, report);
    bench_paths(base, shared, o, report);
    if (o.sensors.empty() ||
        std::find(o.sensors.begin(), o.sensors.end(), "gmapd-32x32") != o.sensors.end())
        report.photon.push_back(photon_row(base, shared, o));
    if (!o.throughput_only) {  // a partial run writes no report files
        bench_las_rate(shared, o, report);
        bench_errors(base, o.quick, report);
        write_reports(report, o.out_dir);
        fmt::print("reports: {}/report.md, report.json, time_vs_error.svg\n", o.out_dir);
    }
    check_ceiling(report);
}

}  // namespace

void register_bench(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "bench", "Benchmark: pipeline vs Embree ceiling, BVH, LAS rate, time vs error");
    auto o = std::make_shared<Opts>();
    cmd->add_option("--out-dir", o->out_dir,
                    "Where report.md, report.json and time_vs_error.svg go")
        ->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--seconds", o->seconds, "Simulated seconds per throughput run")
        ->capture_default_str();
    cmd->add_flag("--quick", o->quick, "Short run for CI (small durations, fewer settings)");
    cmd->add_option("--sensor", o->sensors,
                    "Only these sensors (vlp16, hdl64e-s3, als-mirror, gmapd-32x32); repeatable");
    cmd->add_option("--sub-rays", o->sub_rays, "Only these sub-ray counts; repeatable");
    cmd->add_flag("--throughput-only", o->throughput_only,
                  "Skip the LAS-rate and run-time-against-error parts");
    auto* repeat_option =
        cmd->add_option("--repeat", o->repeat,
                        "Pipeline and ceiling runs per row, alternating; the best of each is "
                        "reported (--quick: 1)")
            ->check(CLI::Range(1, 20))
            ->capture_default_str();
    cmd->callback([o, repeat_option] {
        o->repeat_given = repeat_option->count() > 0;
        run_bench(*o);
    });
}

}  // namespace mirage::hil
