// SPDX-License-Identifier: Apache-2.0
// `mirage demo`: the demo town seen by a VLP-16 on a car and by an airborne mirror scanner;
// LAS files and PNG previews in the output folder.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "commands.hpp"
#include "demo_photon.hpp"
#include "job.hpp"
#include "las_options.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/image/preview.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "progress.hpp"
#include "summary.hpp"
#include "waveform_preview.hpp"

namespace mirage::hil {
namespace {

struct DemoRun {
    const char* name;
    const char* sensor;
    const char* trajectory;
    const char* seconds;
    LasChoice las = {};
};

// Range image of the last revolution (spinning) or of the scan lines (airborne).
void write_range_preview(const std::string& path, const std::vector<core::PointRecord>& points,
                         const Job& job) {
    if (points.empty()) return;
    if (job.sensor.airborne) {
        // Columns = pulses per scan line, from the first two end-of-line flags.
        std::uint64_t first_edge = 0, line = 0;
        bool seen = false;
        for (const auto& p : points) {
            if (!p.edge_of_flight_line) continue;
            if (seen && p.pulse > first_edge) {
                line = p.pulse - first_edge;
                break;
            }
            first_edge = p.pulse;
            seen = true;
        }
        if (line == 0) return;
        const int cols = static_cast<int>(std::min<std::uint64_t>(line, 65536));
        image::write_range_png(path, points, 1000, cols, image::RangeImageLayout::Airborne);
        return;
    }
    // Spinning: the last revolution, rows ordered by elevation (top row = highest beam).
    const auto last_t = points.back().t;
    std::map<std::uint16_t, float> elevation;
    for (const auto& p : points) elevation[p.channel] = p.scan_angle_deg;
    std::vector<std::pair<float, std::uint16_t>> order;
    for (auto [ch, el] : elevation) order.push_back({-el, ch});
    std::sort(order.begin(), order.end());
    std::map<std::uint16_t, std::uint16_t> row;
    for (std::size_t i = 0; i < order.size(); ++i)
        row[order[i].second] = static_cast<std::uint16_t>(i);
    std::vector<core::PointRecord> rev;
    for (const auto& p : points)
        if (last_t - p.t < std::chrono::milliseconds(100)) {
            rev.push_back(p);
            rev.back().channel = row[p.channel];
        }
    image::write_range_png(path, rev, static_cast<int>(order.size()), 1800,
                           image::RangeImageLayout::Spinning,
                           std::max(1, 256 / static_cast<int>(order.size())));
}

void run_one(const DemoRun& run, const std::string& scene_spec, const std::filesystem::path& dir,
             std::uint64_t seed, int threads, const std::shared_ptr<const scene::Scene>& scene,
             double scene_seconds, std::shared_ptr<const render::EmbreeRenderer>& renderer) {
    JobInputs in;
    in.scene = scene_spec;
    in.sensor = run.sensor;
    in.trajectory = run.trajectory;
    in.duration = run.seconds;
    in.seed = seed;
    in.threads = threads;
    // The scene and BVH are built once and shared by both runs.
    Job job = load_job_with_scene(in, scene, scene_seconds, /*build_renderer=*/false);
    if (!renderer) renderer = std::make_shared<render::EmbreeRenderer>(*scene);
    job.renderer = renderer;

    const auto las_path = dir / fmt::format("demo_{}.las", run.name);
    const auto csv_path = dir / fmt::format("demo_{}_trajectory.csv", run.name);
    core::save_trajectory_csv(csv_path.string(), job.trajectory);
    las::LasWriter writer(las_path.string(), job.scene->georef, writer_options(run.las, job));
    std::vector<core::PointRecord> points;
    // Reserve up front: growing a multi-gigabyte vector while rendering stalls the writer thread.
    points.reserve(job.sensor.scan->pulse_count(job.options.duration));
    las::LasSink sink(writer, &points);
    fmt::print("\n== {}: {} along {} for {} s ==\n", run.name, run.sensor, run.trajectory,
               run.seconds);
    ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
    const auto stats =
        render::render(job.setup(), sink, [&](const render::RenderStats& s) { bar.update(s); });
    bar.finish(stats);
    print_summary(stdout, "demo", job, stats);

    const auto top_h = dir / fmt::format("demo_{}_height.png", run.name);
    const auto top_i = dir / fmt::format("demo_{}_intensity.png", run.name);
    const auto range = dir / fmt::format("demo_{}_range.png", run.name);
    image::write_topdown_png(top_h.string(), points, image::TopdownMode::Height);
    image::write_topdown_png(top_i.string(), points, image::TopdownMode::Intensity);
    write_range_preview(range.string(), points, job);
    fmt::print(
        "  LAS        {}\n  trajectory {}\n  previews   {}\n             {}\n             {}\n",
        las_path.string(), csv_path.string(), top_h.string(), top_i.string(), range.string());
    if (run.las.waveform) {
        const auto png = dir / fmt::format("demo_{}_waveforms.png", run.name);
        write_waveform_preview(png.string(), las::LasFile::read(las_path.string()), {});
    }
}

}  // namespace

void register_demo(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "demo",
        "Render the demo town: VLP-16 car drive, airborne mirror flight, a full-waveform "
        "flight and a photon-counting pass over a camouflaged vehicle");
    struct Opts {
        std::string out_dir = ".";
        std::uint64_t seed = 1;
        int threads = 0;
        std::string car_seconds = "10";
        std::string flight_seconds = "6";
        std::string waveform_seconds = "0.25";
        std::string photon_seconds = "1.8";
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("--out-dir", o->out_dir, "Where the LAS files and previews go")
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "Town and noise seed")->capture_default_str();
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--car-seconds", o->car_seconds, "Length of the drive")->capture_default_str();
    cmd->add_option("--flight-seconds", o->flight_seconds, "Length of the flight")
        ->capture_default_str();
    cmd->add_option("--waveform-seconds", o->waveform_seconds,
                    "Length of the full-waveform flight (0: none)")
        ->capture_default_str();
    cmd->add_option("--photon-seconds", o->photon_seconds,
                    "Length of the photon-counting pass over the camouflaged vehicle (0: none)")
        ->capture_default_str();
    cmd->callback([o] {
        const std::filesystem::path dir = std::filesystem::absolute(o->out_dir).lexically_normal();
        std::filesystem::create_directories(dir);
        las::install_signal_finalizer();
        const std::string scene_spec = fmt::format("demo:{}", o->seed);
        double scene_seconds = 0;
        const auto scene = load_scene_timed(scene_spec, scene_seconds);
        fmt::print(
            "demo town (seed {}): {} triangles placed, {} materials, generated in {:.2f} s\n",
            o->seed, scene->placed_triangle_count(), scene->materials.size(), scene_seconds);
        std::shared_ptr<const render::EmbreeRenderer> renderer;
        run_one({"vlp16", "vlp16", "demo-car", o->car_seconds.c_str()}, scene_spec, dir, o->seed,
                o->threads, scene, scene_seconds, renderer);
        run_one({"als", "als-mirror", "demo-flight", o->flight_seconds.c_str()}, scene_spec, dir,
                o->seed, o->threads, scene, scene_seconds, renderer);
        // Waveforms recorded over 256 samples (38 m): a roof edge or a crown and the ground.
        if (parse_seconds(o->waveform_seconds, "--waveform-seconds").count() > 0)
            run_one({"als_waveform",
                     "als-waveform",
                     "demo-flight",
                     o->waveform_seconds.c_str(),
                     {6, 0.001, true, 256, false}},
                    scene_spec, dir, o->seed, o->threads, scene, scene_seconds, renderer);
        if (parse_seconds(o->photon_seconds, "--photon-seconds").count() > 0)
            run_photon_demo({scene_spec, o->photon_seconds, o->seed, o->threads}, dir, scene,
                            scene_seconds, renderer);
        fmt::print("\nDemo outputs are in {}\n", dir.string());
    });
}

}  // namespace mirage::hil
