// SPDX-License-Identifier: Apache-2.0
// `mirage render`: scene + sensor + trajectory -> LAS file.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "commands.hpp"
#include "job.hpp"
#include "las_options.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "progress.hpp"
#include "summary.hpp"

namespace mirage::hil {
namespace {

struct Opts {
    JobInputs job;
    std::string out;
    LasChoice las;
};

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
    cmd->callback([opts] {
        Job job = load_job(opts->job);
        std::fprintf(stderr, "%s", sensor::describe(job.sensor).c_str());
        las::LasWriterOptions lo = writer_options(opts->las, job);
        las::install_signal_finalizer();
        las::LasWriter writer(opts->out, job.scene->georef, lo);
        las::LasSink sink(writer);
        ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
        const auto stats =
            render::render(job.setup(), sink, [&](const render::RenderStats& s) { bar.update(s); });
        bar.finish(stats);
        print_summary(stdout, "render", job, stats);
        std::printf("  wrote %s (LAS 1.4, point format %d, %llu points)\n", opts->out.c_str(),
                    lo.point_format, static_cast<unsigned long long>(writer.points_written()));
    });
}

}  // namespace mirage::hil
