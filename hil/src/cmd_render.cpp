// SPDX-License-Identifier: Apache-2.0
// `mirage render`: scene + sensor + trajectory -> LAS file.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

#include "coincidence_output.hpp"
#include "commands.hpp"
#include "job.hpp"
#include "las_options.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/render/coincidence.hpp"
#include "progress.hpp"
#include "summary.hpp"

namespace mirage::hil {
namespace {

struct Opts {
    JobInputs job;
    std::string out;
    LasChoice las;
    std::string coincidence;  // the coincidence-processed points' LAS file (Geiger sensors)
    render::CoincidenceParams cp;
};

// The events through the coincidence processor into o.coincidence.
void write_coincidence(const Opts& o, const Job& job, const las::LasWriterOptions& lo,
                       std::span<const render::FirstEvent> events) {
    render::CoincidenceStats st;
    const auto pts = render::coincidence(job.setup(), events, o.cp, &st);
    write_coincidence_las(o.coincidence, job, lo, coincidence_records(pts, job));
    std::printf(
        "  coincidence: %llu gates over %llu cells of %.2f m (%.1f gates per cell), "
        "%llu first events, noise %.3g per gate and %.2f m bin -> %llu points in %s\n",
        static_cast<unsigned long long>(st.gates), static_cast<unsigned long long>(st.cells),
        o.cp.cell_m, st.cells ? double(st.gates) / double(st.cells) : 0.0,
        static_cast<unsigned long long>(st.events), st.noise_per_bin, o.cp.bin_m,
        static_cast<unsigned long long>(st.points), o.coincidence.c_str());
}

}  // namespace

void register_render(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "render", "Render a scene with a sensor along a trajectory into a LAS file");
    auto opts = std::make_shared<Opts>();
    add_job_options(*cmd, opts->job);
    cmd->add_option("--out", opts->out, "Output LAS 1.4 file")->required();
    cmd->add_option("--format", opts->las.format,
                    "LAS point format: 1, 3, 6 or 7; with waveforms 4, 5, 9 or 10")
        ->check(CLI::IsMember({1, 3, 4, 5, 6, 7, 9, 10}))
        ->capture_default_str();
    cmd->add_flag("--waveform", opts->las.waveform,
                  "Record each pulse's digitised waveform (linear detector): point format 1, 3, "
                  "6, 7 becomes 4, 5, 9, 10");
    cmd->add_option("--waveform-samples", opts->las.waveform_samples,
                    "Samples recorded per pulse, from its first arrival")
        ->check(CLI::Range(1u, 65536u))
        ->capture_default_str();
    cmd->add_flag("--wdp", opts->las.wdp,
                  "Keep the waveform packets in an external .wdp file beside the LAS file");
    cmd->add_option("--scale", opts->las.scale, "LAS coordinate scale in metres")
        ->capture_default_str();
    cmd->add_option("--coincidence", opts->coincidence,
                    "Geiger-mode sensors: also write the coincidence-processed points to this LAS "
                    "file (first events per ground cell and height bin, Coates' correction)");
    cmd->add_option("--cell", opts->cp.cell_m, "Coincidence ground cell side, m")
        ->check(CLI::Range(1e-3, 1e3))
        ->capture_default_str();
    cmd->add_option("--bin", opts->cp.bin_m, "Coincidence height bin, m")
        ->check(CLI::Range(1e-3, 1e3))
        ->capture_default_str();
    cmd->add_option("--min-events", opts->cp.min_events,
                    "Coincidence: events a bin needs at least to become a point")
        ->check(CLI::Range(1u, 1000000u))
        ->capture_default_str();
    cmd->add_option("--pulses-per-cell", opts->cp.gates_per_cell,
                    "Coincidence: each cell counts only its first N gates in time, a dwell of N "
                    "pulses (0: all)")
        ->check(CLI::Range(0u, 100000000u))
        ->capture_default_str();
    cmd->callback([opts, cmd] {
        for (const char* o : {"--cell", "--bin", "--min-events", "--pulses-per-cell"})
            if (opts->coincidence.empty() && cmd->count(o) > 0)
                throw mirage::ConfigError(std::string("render ") + o + ": only with --coincidence");
        Job job = load_job(opts->job);
        std::fprintf(stderr, "%s", sensor::describe(job.sensor).c_str());
        if (!opts->coincidence.empty() && job.sensor.detector != sensor::DetectorKind::Geiger)
            throw mirage::ConfigError("render --coincidence: sensor '" + job.sensor.name +
                                      "' has no Geiger-mode detector (detector.type: geiger)");
        las::LasWriterOptions lo = writer_options(opts->las, job);
        las::install_signal_finalizer();
        las::LasWriter writer(opts->out, job.scene->georef, lo);
        las::LasSink las_sink(writer);
        render::FirstEventSink tee(&las_sink);
        render::PointSink& sink =
            opts->coincidence.empty() ? static_cast<render::PointSink&>(las_sink) : tee;
        ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
        const auto stats =
            render::render(job.setup(), sink, [&](const render::RenderStats& s) { bar.update(s); });
        bar.finish(stats);
        print_summary(stdout, "render", job, stats);
        std::printf("  wrote %s (LAS 1.4, point format %d, %llu points)\n", opts->out.c_str(),
                    lo.point_format, static_cast<unsigned long long>(writer.points_written()));
        if (!opts->coincidence.empty()) write_coincidence(*opts, job, lo, tee.events);
    });
}

}  // namespace mirage::hil
