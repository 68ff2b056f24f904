// SPDX-License-Identifier: Apache-2.0
// `mirage demo`: the demo town seen by a VLP-16 on a car and by an airborne mirror scanner;
// LAS files and PNG previews in the output folder.
#include <fmt/format.h>

#include <filesystem>

#include "commands.hpp"
#include "job.hpp"
#include "las_sink.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/image/preview.hpp"
#include "mirage/las/las_writer.hpp"
#include "progress.hpp"
#include "summary.hpp"

namespace mirage::hil {
namespace {

struct DemoRun {
    const char* name;
    const char* sensor;
    const char* trajectory;
    const char* seconds;
};

// Range image of the last revolution (spinning) or of the scan lines (airborne).
void write_range_preview(const std::string& path, const std::vector<core::PointRecord>& points, const Job& job) {
    (void)path; (void)points; (void)job;  // TODO: wire to image::write_range_png once its API lands
}

void run_one(const DemoRun& run, const std::string& scene_spec, const std::filesystem::path& dir,
             std::uint64_t seed, int threads, const std::shared_ptr<const scene::Scene>& scene,
             double scene_seconds,
             std::unique_ptr<render::EmbreeRenderer>& renderer) {
    JobInputs in;
    in.scene = scene_spec;
    in.sensor = run.sensor;
    in.trajectory = run.trajectory;
    in.duration = run.seconds;
    in.seed = seed;
    in.threads = threads;
    // The scene and BVH are built once and shared by both runs.
    Job job = load_job_with_scene(in, scene, scene_seconds, /*build_renderer=*/false);
    if (!renderer) renderer = std::make_unique<render::EmbreeRenderer>(*scene);
    job.renderer = std::move(renderer);

    const auto las_path = dir / fmt::format("demo_{}.las", run.name);
    const auto csv_path = dir / fmt::format("demo_{}_trajectory.csv", run.name);
    core::save_trajectory_csv(csv_path.string(), job.trajectory);
    las::LasWriterOptions lo;
    lo.file_source_id = job.sensor.point_source_id;
    las::LasWriter writer(las_path.string(), job.scene->georef, lo);
    std::vector<core::PointRecord> points;
    LasSink sink(writer, &points);
    fmt::print("\n== {}: {} along {} for {} s ==\n", run.name, run.sensor, run.trajectory, run.seconds);
    ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
    const auto stats = render::render(*job.scene, *job.renderer, job.sensor, job.trajectory, job.mount, job.env,
                                      job.options, sink, [&](const render::RenderStats& s) { bar.update(s); });
    bar.finish(stats);
    writer.close();
    print_summary(stdout, "demo", job, stats);

    const auto top_h = dir / fmt::format("demo_{}_height.png", run.name);
    const auto top_i = dir / fmt::format("demo_{}_intensity.png", run.name);
    const auto range = dir / fmt::format("demo_{}_range.png", run.name);
    image::write_topdown_png(top_h.string(), points, image::TopdownMode::Height);
    image::write_topdown_png(top_i.string(), points, image::TopdownMode::Intensity);
    write_range_preview(range.string(), points, job);
    fmt::print("  LAS        {}\n  trajectory {}\n  previews   {}\n             {}\n             {}\n",
               las_path.string(), csv_path.string(), top_h.string(), top_i.string(), range.string());
    renderer = std::move(job.renderer);
}

}  // namespace

void register_demo(CLI::App& app) {
    auto* cmd = app.add_subcommand("demo", "Render the demo town: VLP-16 car drive and airborne mirror flight");
    struct Opts {
        std::string out_dir = ".";
        std::uint64_t seed = 1;
        int threads = 0;
        std::string car_seconds = "10";
        std::string flight_seconds = "6";
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--out-dir", o->out_dir, "Where the LAS files and previews go")->capture_default_str();
    cmd->add_option("--seed", o->seed, "Town and noise seed")->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")->capture_default_str();
    cmd->add_option("--car-seconds", o->car_seconds, "Length of the drive")->capture_default_str();
    cmd->add_option("--flight-seconds", o->flight_seconds, "Length of the flight")->capture_default_str();
    cmd->callback([o] {
        const std::filesystem::path dir = std::filesystem::absolute(o->out_dir);
        std::filesystem::create_directories(dir);
        las::install_signal_finalizer();
        const std::string scene_spec = fmt::format("demo:{}", o->seed);
        double scene_seconds = 0;
        const auto scene = load_scene_timed(scene_spec, scene_seconds);
        fmt::print("demo town (seed {}): {} triangles placed, {} materials, generated in {:.2f} s\n", o->seed,
                   scene->placed_triangle_count(), scene->materials.size(), scene_seconds);
        std::unique_ptr<render::EmbreeRenderer> renderer;
        run_one({"vlp16", "vlp16", "demo-car", o->car_seconds.c_str()}, scene_spec, dir, o->seed, o->threads,
                scene, scene_seconds, renderer);
        run_one({"als", "als-mirror", "demo-flight", o->flight_seconds.c_str()}, scene_spec, dir, o->seed,
                o->threads, scene, scene_seconds, renderer);
        fmt::print("\nDemo outputs are in {}\n", dir.string());
    });
}

}  // namespace mirage::hil
