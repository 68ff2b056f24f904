// SPDX-License-Identifier: Apache-2.0
// `mirage render`: scene + sensor + trajectory -> LAS file.
#include <fmt/format.h>

#include <cstdio>

#include "commands.hpp"
#include "job.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "progress.hpp"
#include "summary.hpp"

namespace mirage::hil {

void register_render(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "render", "Render a scene with a sensor along a trajectory into a LAS file");
    struct Opts {
        JobInputs job;
        std::string out;
        int format = 6;
        double scale = 0.001;
    };
    auto opts = std::make_shared<Opts>();
    add_job_options(*cmd, opts->job);
    cmd->add_option("--out", opts->out, "Output LAS 1.4 file")->required();
    cmd->add_option("--format", opts->format, "LAS point format: 1, 3, 6 or 7")
        ->check(CLI::IsMember({1, 3, 6, 7}))
        ->capture_default_str();
    cmd->add_option("--scale", opts->scale, "LAS coordinate scale in metres")
        ->capture_default_str();
    cmd->callback([opts] {
        Job job = load_job(opts->job);
        std::fprintf(stderr, "%s", sensor::describe(job.sensor).c_str());
        las::LasWriterOptions lo;
        lo.point_format = static_cast<std::uint8_t>(opts->format);
        lo.scale = opts->scale;
        lo.file_source_id = job.sensor.point_source_id;
        las::install_signal_finalizer();
        las::LasWriter writer(opts->out, job.scene->georef, lo);
        las::LasSink sink(writer);
        ProgressBar bar(job.sensor.scan->pulse_count(job.options.duration));
        const auto stats =
            render::render(job.setup(), sink, [&](const render::RenderStats& s) { bar.update(s); });
        bar.finish(stats);
        print_summary(stdout, "render", job, stats);
        std::printf("  wrote %s (LAS 1.4, point format %d, %llu points)\n", opts->out.c_str(),
                    opts->format, static_cast<unsigned long long>(writer.points_written()));
    });
}

}  // namespace mirage::hil
