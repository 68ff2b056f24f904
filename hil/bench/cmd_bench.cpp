// SPDX-License-Identifier: Apache-2.0
// `mirage bench`: throughput of the whole pipeline against the bare Embree ceiling on the same
// rays, BVH build and memory, LAS write rate, and run time against error.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <barrier>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unordered_map>

#include "bench_report.hpp"
#include "commands.hpp"
#include "job.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"

namespace mirage::hil {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Bare Embree on exactly the pipeline's rays, all threads tracing at once: in each round every
// thread first generates its next chunks (untimed), then all trace them together between two
// barriers, timed by the wall clock. Timing each thread's intersect calls alone would let one
// thread trace while the other generates rays, sharing the cores and caches less than the
// pipeline does, and overstate the ceiling. Returns rays/s over `threads` threads.
double ceiling_rays_per_s(const Job& job, int threads, std::uint64_t pulses,
                          std::uint64_t& rays_out) {
    const std::size_t chunk = render::chunk_pulses(job.sensor, job.options.chunk_pulses);
    const std::uint64_t chunks = (pulses + chunk - 1) / chunk;
    constexpr std::uint64_t kChunksPerRound = 8;  // per thread: ~64 k pulses, a few 10 MB of rays
    const std::uint64_t per_round = kChunksPerRound * static_cast<std::uint64_t>(threads);
    const std::uint64_t rounds = (chunks + per_round - 1) / per_round;
    std::atomic<std::uint64_t> rays{0};
    std::barrier sync(threads);
    Clock::time_point round_start;
    double traced_s = 0;  // written by thread 0 only, between barriers
    std::vector<std::thread> pool;
    for (int w = 0; w < threads; ++w) {
        pool.emplace_back([&, w] {
            std::vector<std::vector<render::Ray>> batch;
            render::TraceBatches batches(job.setup());
            std::vector<render::Hit> hits;
            for (std::uint64_t round = 0; round < rounds; ++round) {
                batch.clear();
                for (std::uint64_t k = 0; k < kChunksPerRound; ++k) {
                    const std::uint64_t c = round * per_round +
                                            k * static_cast<std::uint64_t>(threads) +
                                            static_cast<std::uint64_t>(w);
                    if (c >= chunks) break;
                    const std::uint64_t first = c * chunk;
                    const auto n =
                        static_cast<std::size_t>(std::min<std::uint64_t>(chunk, pulses - first));
                    std::vector<render::Ray> rays;
                    batches.for_each(first, n, [&](std::span<const render::Ray> r) {
                        rays.insert(rays.end(), r.begin(), r.end());
                    });
                    batch.push_back(std::move(rays));
                }
                sync.arrive_and_wait();
                if (w == 0) round_start = Clock::now();
                sync.arrive_and_wait();
                for (const auto& r : batch) {
                    hits.resize(r.size());
                    job.renderer->intersect(r, hits);
                    rays += r.size();
                }
                sync.arrive_and_wait();
                if (w == 0) traced_s += seconds_since(round_start);
            }
        });
    }
    for (auto& t : pool) t.join();
    rays_out = rays.load();
    return traced_s > 0 ? double(rays_out) / traced_s : 0.0;
}

render::RenderStats run_pipeline_to_null(Job& job, const std::string& null_path) {
    las::LasWriter writer(null_path, job.scene->georef);
    las::LasSink sink(writer);
    return render::render(job.setup(), sink);
}

// Per-pulse first-return range and intensity, for error against a reference.
struct Sample {
    float range;
    std::uint16_t intensity;
};
class KeepSink : public render::PointSink {
  public:
    void write(std::span<const core::PointRecord> pts) override {
        for (const auto& p : pts)
            if (p.return_number == 1) by_pulse.emplace(p.pulse, Sample{p.range_m, p.intensity});
    }
    std::unordered_map<std::uint64_t, Sample> by_pulse;
};

}  // namespace

void register_bench(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "bench", "Benchmark: pipeline vs Embree ceiling, BVH, LAS rate, time vs error");
    struct Opts {
        std::string out_dir = "bench-results";
        int threads = 0;
        std::string seconds =
            "20";  // simulated seconds per throughput configuration (warm-up < 3 %)
        bool quick = false;
        std::vector<std::string> sensors;  // empty: all
        std::vector<int> sub_rays;         // empty: 1, 7, 19
        bool throughput_only = false;
        int repeat = 3;  // pipeline/ceiling pairs per row (--quick: 1)
    };
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
                    "Only these throughput sensors (vlp16, hdl64e-s3, als-mirror); repeatable");
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
        const int threads =
            o->threads > 0 ? o->threads : static_cast<int>(std::thread::hardware_concurrency());
        std::filesystem::create_directories(o->out_dir);
        BenchReport report;
        report.machine = machine_description(threads);
        const std::string sim = o->quick ? "0.05" : o->seconds;

        // Scene and BVH once.
        double scene_s = 0;
        const auto town = load_scene_timed("demo", scene_s);
        report.scene_seconds = scene_s;
        report.triangles_placed = town->placed_triangle_count();
        JobInputs base;
        base.scene = "demo";
        base.threads = threads;
        Job shared = load_job_with_scene(base, town, scene_s);
        const auto& bs = shared.renderer->build_stats();
        report.bvh_build_seconds = bs.build_seconds;
        report.bvh_bytes = bs.bvh_bytes;
        report.unique_triangles = bs.triangles;
        fmt::print(
            "demo town: {} placed / {} stored triangles, scene {:.2f} s, BVH {:.3f} s, {:.1f} MB "
            "({:.1f} B per stored triangle)\n",
            bs.placed_triangles, bs.triangles, scene_s, bs.build_seconds,
            double(bs.bvh_bytes) / 1e6,
            double(bs.bvh_bytes) / double(std::max<std::uint64_t>(1, bs.triangles)));

        struct Config {
            const char* sensor;
            const char* trajectory;
        };
        const Config configs[] = {
            {"vlp16", "demo-car"}, {"hdl64e-s3", "demo-car"}, {"als-mirror", "demo-flight"}};
        const std::vector<int> sub_rays =
            o->sub_rays.empty() ? std::vector<int>{1, 7, 19} : o->sub_rays;
        for (const auto& c : configs) {
            if (!o->sensors.empty() &&
                std::find(o->sensors.begin(), o->sensors.end(), c.sensor) == o->sensors.end())
                continue;
            for (int s : sub_rays) {
                if (o->quick && s == 19 && o->sub_rays.empty()) continue;
                JobInputs in = base;
                in.sensor = c.sensor;
                in.trajectory = c.trajectory;
                in.duration = sim;
                in.sub_rays = s;
                Job job = load_job_with_scene(in, town, scene_s, false);
                job.renderer = shared.renderer;
                const std::uint64_t pulses = job.sensor.scan->pulse_count(job.options.duration);
                ThroughputRow row;
                row.sensor = c.sensor;
                row.sub_rays = s;
                row.pulses = pulses;
                row.real_pulse_rate = job.sensor.scan->pulse_rate_hz();
                // Pipeline and ceiling alternate, so a stretch of load from elsewhere on the
                // machine disturbs one run of each kind, not all runs of one kind.
                row.repeats = o->quick && repeat_option->count() == 0 ? 1 : o->repeat;
                for (int k = 0; k < row.repeats; ++k) {
                    std::uint64_t rays = 0;
                    const double ceiling_rays = ceiling_rays_per_s(job, threads, pulses, rays);
                    const double ceiling_pulses =
                        ceiling_rays / double(std::max<std::uint64_t>(1, rays)) * double(pulses);
                    const auto run = run_pipeline_to_null(job, "/dev/null");
                    const double pipeline_pulses = double(run.pulses) / run.seconds;
                    const double pair = ceiling_pulses > 0 ? pipeline_pulses / ceiling_pulses : 0;
                    row.ratio_min = k == 0 ? pair : std::min(row.ratio_min, pair);
                    row.ratio_max = k == 0 ? pair : std::max(row.ratio_max, pair);
                    if (ceiling_pulses > row.ceiling_pulses_per_s) {
                        row.ceiling_pulses_per_s = ceiling_pulses;
                        row.ceiling_rays_per_s = ceiling_rays;
                    }
                    if (pipeline_pulses > row.pipeline_pulses_per_s) {
                        row.pipeline_pulses_per_s = pipeline_pulses;
                        row.pipeline_points_per_s = double(run.points) / run.seconds;
                        row.points = run.points;
                    }
                }
                const double ceiling_rays = row.ceiling_rays_per_s;
                report.throughput.push_back(row);
                fmt::print(
                    "{:>11} sub-rays {:>2}: pipeline {:6.2f} M pulses/s ({:6.2f} M points/s) | "
                    "ceiling "
                    "{:6.2f} M pulses/s ({:6.1f} M rays/s) | ratio {:.2f} (pairs {:.2f}–{:.2f}, "
                    "{} runs) | {:6.1f}x real time\n",
                    c.sensor, s, row.pipeline_pulses_per_s / 1e6, row.pipeline_points_per_s / 1e6,
                    row.ceiling_pulses_per_s / 1e6, ceiling_rays / 1e6, row.ratio(), row.ratio_min,
                    row.ratio_max, row.repeats, row.x_real_time());
            }
        }

        if (o->throughput_only) return;  // partial run: no report files
        // LAS write rate to a real file.
        {
            const std::uint64_t n = o->quick ? 500'000 : 5'000'000;
            std::vector<core::PointRecord> pts(65536);
            for (std::size_t i = 0; i < pts.size(); ++i) {
                pts[i].x = double(i % 1000);
                pts[i].y = double(i / 1000);
                pts[i].z = 1.5;
                pts[i].intensity = static_cast<std::uint16_t>(i);
            }
            const auto path = (std::filesystem::path(o->out_dir) / "las_rate.las").string();
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

        // Run time against error: VLP-16 on the car drive, noise off, against a high-fidelity
        // reference (37 sub-rays), which is itself compared with a denser render (61 sub-rays)
        // to show it converged. The BVH quality changes build and trace time but never a hit, so
        // errors are measured once per sub-ray count and the qualities get timing rows.
        {
            const std::string err_sim = o->quick ? "0.05" : "1";
            auto render_keep = [&](int s, const std::string& quality, double& secs,
                                   BvhRow* bvh = nullptr) {
                JobInputs in = base;
                in.sensor = "vlp16";
                in.trajectory = "demo-car";
                in.duration = err_sim;
                in.sub_rays = s;
                in.no_noise = true;
                in.quality = quality;
                Job job = load_job_with_scene(in, town, scene_s, true);
                KeepSink keep;
                const auto st = render::render(job.setup(), keep);
                secs = st.seconds;
                if (bvh) {
                    bvh->build_seconds = job.renderer->build_stats().build_seconds;
                    bvh->bvh_bytes = job.renderer->build_stats().bvh_bytes;
                    bvh->rays = st.rays;
                }
                return keep;
            };
            // Pulses are paired by index; VLP-16 keeps one return per pulse (the strongest), so
            // the first return is the pulse's only one.
            // A return over c·τ/2 (0.75 m) from the reference's lies on another surface: where
            // two surfaces share a beam about equally the strongest flips, metres at a time, and
            // such pulses dominate the range RMS; they are counted apart as well.
            auto compare = [](const KeepSink& got, const KeepSink& ref, ErrorRow& e) {
                double sr = 0, si = 0, ss = 0;
                std::uint64_t both = 0, differ = 0, switched = 0;
                std::vector<double> abs_err;
                abs_err.reserve(ref.by_pulse.size());
                for (const auto& [pulse, r] : ref.by_pulse) {
                    const auto it = got.by_pulse.find(pulse);
                    if (it == got.by_pulse.end()) {
                        ++differ;
                        continue;
                    }
                    const double dr = double(it->second.range) - double(r.range);
                    const double di = double(it->second.intensity) - double(r.intensity);
                    sr += dr * dr;
                    if (std::abs(dr) > 0.75)
                        ++switched;
                    else
                        ss += dr * dr;
                    abs_err.push_back(std::abs(dr));
                    si += di * di;
                    ++both;
                }
                for (const auto& [pulse, r] : got.by_pulse)
                    if (!ref.by_pulse.count(pulse)) ++differ;
                e.range_rms_m = both ? std::sqrt(sr / double(both)) : 0.0;
                e.same_surface_range_rms_m =
                    both > switched ? std::sqrt(ss / double(both - switched)) : 0.0;
                e.other_surface = both ? double(switched) / double(both) : 0.0;
                if (!abs_err.empty()) {
                    // RMS is dominated by edge pulses whose strongest return switches surface;
                    // the median and p95 show the typical error.
                    std::sort(abs_err.begin(), abs_err.end());
                    e.range_p50_m = abs_err[abs_err.size() / 2];
                    e.range_p95_m = abs_err[abs_err.size() * 95 / 100];
                }
                e.intensity_rms = both ? std::sqrt(si / double(both)) : 0.0;
                e.presence_mismatch =
                    double(differ) / double(std::max<std::size_t>(1, ref.by_pulse.size()));
            };
            auto print = [](const ErrorRow& e) {
                fmt::print(
                    "error: {:>2} sub-rays against {}: {:.3f} s, range RMS {:.4f} m (p50 {:.2f} "
                    "mm, p95 {:.1f} mm; {:.2f} % on another surface, {:.2f} mm RMS on the same), "
                    "intensity RMS {:.1f}, return presence differs {:.2f} %\n",
                    e.sub_rays, e.reference_sub_rays, e.seconds, e.range_rms_m, e.range_p50_m * 1e3,
                    e.range_p95_m * 1e3, 100.0 * e.other_surface, e.same_surface_range_rms_m * 1e3,
                    e.intensity_rms, 100.0 * e.presence_mismatch);
            };
            constexpr int kReference = 37, kDense = 61;
            double ref_secs = 0;
            const KeepSink ref = render_keep(kReference, "medium", ref_secs);
            for (int s : {1, 7, 19}) {
                ErrorRow e;
                e.sub_rays = s;
                e.reference_sub_rays = kReference;
                e.reference_seconds = ref_secs;
                compare(render_keep(s, "medium", e.seconds), ref, e);
                report.errors.push_back(e);
                print(e);
            }
            // The reference against a denser one: its own error, to compare the rows above with.
            ErrorRow conv;
            conv.sub_rays = kReference;
            conv.reference_sub_rays = kDense;
            conv.seconds = ref_secs;
            compare(ref, render_keep(kDense, "medium", conv.reference_seconds), conv);
            report.errors.push_back(conv);
            print(conv);
            // BVH qualities: build time and memory, and the render time of the same job.
            for (const char* q : {"low", "medium", "high"}) {
                if (o->quick && std::string(q) != "medium") continue;
                BvhRow b;
                b.quality = q;
                b.sub_rays = 19;
                render_keep(b.sub_rays, q, b.render_seconds, &b);
                report.bvh.push_back(b);
                fmt::print(
                    "BVH {:>6}: built in {:.3f} s ({:.1f} MB), render {:.3f} s ({:.1f} M "
                    "rays/s)\n",
                    q, b.build_seconds, double(b.bvh_bytes) / 1e6, b.render_seconds,
                    b.render_seconds > 0 ? double(b.rays) / b.render_seconds / 1e6 : 0.0);
            }
        }
        write_reports(report, o->out_dir);
        fmt::print("reports: {}/report.md, report.json, time_vs_error.svg\n", o->out_dir);
    });
}

}  // namespace mirage::hil
