// SPDX-License-Identifier: Apache-2.0
#include "demo_photon.hpp"

#include <fmt/format.h>

#include <cmath>

#include "coincidence_output.hpp"
#include "job.hpp"
#include "las_options.hpp"
#include "mirage/image/class_views.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/render/coincidence.hpp"
#include "mirage/scene/demo_town.hpp"
#include "progress.hpp"
#include "summary.hpp"

namespace mirage::hil {
namespace {

constexpr double kFrame = 20.0;  // m: the square around the vehicle that is shown
// Processed 2 m beyond it: a cell's points lie where its gates met the ground, up to ~0.5 m
// from the cell (gates are filed under their mid-gate point, docs/photon-counting.md §5).
constexpr double kBorder = 2.0;
// Events kept this far beyond it: a gate is filed under its mid-gate ground point, up to
// 150 m · tan(7.5° + 1 mrad) ≈ 20 m from where its event lies.
constexpr double kMargin = 20.0;
constexpr std::uint32_t kDwells[] = {60, 240, 480};

// Passes on the points whose ground position lies in `pass` (a pass over a 300 m swath keeps
// only what the processing needs), and keeps a copy of those in `keep` for the views.
class FrameSink : public render::PointSink {
  public:
    FrameSink(render::CoincidenceWindow pass, render::CoincidenceWindow keep,
              render::PointSink& next)
        : pass_(pass), keep_(keep), next_(next) {}
    void write(std::span<const core::PointRecord> points) override {
        buf_.clear();
        for (const auto& p : points) {
            if (!pass_.contains(p.x, p.y)) continue;
            buf_.push_back(p);
            if (keep_.contains(p.x, p.y)) kept.push_back(p);
        }
        if (!buf_.empty()) next_.write(buf_);
    }
    void pulses_done(std::uint64_t next_pulse) override { next_.pulses_done(next_pulse); }
    void finish() override { next_.finish(); }
    std::vector<core::PointRecord> kept;

  private:
    render::CoincidenceWindow pass_, keep_;
    render::PointSink& next_;
    std::vector<core::PointRecord> buf_;
};

// Points per truth class: vehicle (65), net (66), ground (2), other.
std::string by_class(std::span<const core::PointRecord> pts) {
    std::uint64_t vehicle = 0, net = 0, ground = 0;
    for (const auto& p : pts) {
        vehicle += p.classification == 65;
        net += p.classification == 66;
        ground += p.classification == 2;
    }
    return fmt::format("{} points: vehicle {}, net {}, ground {}, other {}", pts.size(), vehicle,
                       net, ground, pts.size() - vehicle - net - ground);
}

void write_views(const std::filesystem::path& dir, const std::string& tag,
                 std::span<const core::PointRecord> pts, const image::GroundFrame& top,
                 const image::GroundFrame& side, double ground_z) {
    image::write_png((dir / fmt::format("demo_photon_{}_top.png", tag)).string(),
                     image::render_lowest_by_class(pts, top));
    image::write_png((dir / fmt::format("demo_photon_{}_side.png", tag)).string(),
                     image::render_section_by_class(pts, side, ground_z - 1.0, ground_z + 5.0));
}

// Where the pass looks: the vehicle, the processed window around it (corners on the cell grid)
// and the two views.
struct Framing {
    Eigen::Vector3d at;
    render::CoincidenceParams cp;
    image::GroundFrame top, side;
};

Framing frame_the_vehicle(std::uint64_t seed) {
    scene::DemoTownOptions town;
    town.seed = seed;
    const core::Pose vehicle = scene::camouflaged_vehicle_pose(town);
    const Eigen::Matrix3d r = vehicle.attitude.toRotationMatrix();
    Framing f;
    f.at = vehicle.position;
    const double cell = f.cp.cell_m;
    const double x0 = cell * std::round((f.at.x() - kFrame / 2) / cell);
    const double y0 = cell * std::round((f.at.y() - kFrame / 2) / cell);
    f.cp.dwells = true;  // one grid, finished at each pulse count per cell
    f.cp.window = render::CoincidenceWindow{x0 - kBorder, y0 - kBorder, x0 + kFrame + kBorder,
                                            y0 + kFrame + kBorder};
    // Top: north up, one pixel per cell. Side: along the vehicle, a 2 m slab through its middle.
    f.top = {{x0 + kFrame / 2, y0 + kFrame / 2}, 0.0, kFrame, kFrame, cell, 8};
    f.side = {{f.at.x(), f.at.y()}, std::atan2(r(1, 0), r(0, 0)), kFrame, 2.0, 0.05, 2};
    return f;
}

Job photon_job(const PhotonDemo& d, const std::shared_ptr<const scene::Scene>& scene,
               double scene_seconds, std::shared_ptr<const render::EmbreeRenderer>& renderer) {
    JobInputs in;
    in.scene = d.scene_spec;
    in.sensor = "gmapd-32x32";
    in.trajectory = "demo-camouflage";
    in.duration = d.seconds;
    in.seed = d.seed;
    in.threads = d.threads;
    in.sun_elevation_deg = -1;  // a night collection: the 2 µs gate is not filled by sunlight
    Job job = load_job_with_scene(in, scene, scene_seconds, /*build_renderer=*/false);
    if (!renderer) renderer = std::make_shared<render::EmbreeRenderer>(*scene);
    job.renderer = renderer;
    return job;
}

}  // namespace

void run_photon_demo(const PhotonDemo& d, const std::filesystem::path& dir,
                     const std::shared_ptr<const scene::Scene>& scene, double scene_seconds,
                     std::shared_ptr<const render::EmbreeRenderer>& renderer) {
    Job job = photon_job(d, scene, scene_seconds, renderer);
    const Framing f = frame_the_vehicle(d.seed);
    const render::CoincidenceWindow& w = *f.cp.window;
    const las::LasWriterOptions lo = writer_options(LasChoice{}, job);
    const auto events_path = dir / "demo_photon_events.las";
    las::LasWriter writer(events_path.string(), job.scene->georef, lo);
    las::LasSink las_sink(writer);
    render::FirstEventSink first(&las_sink);
    FrameSink sink({w.x0 - kMargin, w.y0 - kMargin, w.x1 + kMargin, w.y1 + kMargin}, w, first);
    fmt::print("\n== photon: gmapd-32x32 at night along demo-camouflage for {} s ==\n", d.seconds);
    ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
    const auto stats =
        render::render(job.setup(), sink, [&](const render::RenderStats& s) { bar.update(s); });
    bar.finish(stats);
    print_summary(stdout, "demo", job, stats);
    fmt::print("  vehicle under the net at ({:.1f}, {:.1f}); {} events within {} m of it in {}\n",
               f.at.x(), f.at.y(), writer.points_written(), kFrame / 2 + kBorder + kMargin,
               events_path.string());

    write_views(dir, "events", sink.kept, f.top, f.side, f.at.z());
    const render::CoincidenceGrid grid = render::coincidence_grid(job.setup(), first.events, f.cp);
    for (const std::uint32_t dwell : kDwells) {
        render::CoincidenceStats st;
        const auto recs = coincidence_records(grid.finish(&st, dwell), job);
        const auto path = dir / fmt::format("demo_photon_points_{}.las", dwell);
        write_coincidence_las(path.string(), job, lo, recs);
        write_views(dir, std::to_string(dwell), recs, f.top, f.side, f.at.z());
        fmt::print("  {:3} pulses per cell: {} ({} gates over {} cells) -> {}\n", dwell,
                   by_class(recs), st.gates, st.cells, path.string());
    }
    fmt::print("  views: demo_photon_{{events,60,240,480}}_{{top,side}}.png in {}\n", dir.string());
}

}  // namespace mirage::hil
