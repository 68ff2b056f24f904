// SPDX-License-Identifier: Apache-2.0
// `mirage render`: scene + sensor + trajectory -> LAS file.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "commands.hpp"
#include "job.hpp"
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
    int format = 6;
    double scale = 0.001;
    bool waveform = false;
    std::uint32_t waveform_samples = 256;
    bool wdp = false;
};

// Waveform packets as the digitiser makes them (docs/file-formats.md §6.1): its bits rounded up
// to a byte multiple, its clock in whole ps, and gain and offset that turn stored counts into
// photo-electrons.
las::WaveformPackets packets(const Opts& o, const sensor::SensorModel& sensor) {
    const auto& d = sensor.linear;
    const double period_ps = 1e3 / d.sample_rate_gsps;
    if (std::abs(period_ps - std::round(period_ps)) > 1e-6)
        throw mirage::ConfigError(fmt::format(
            "render --waveform: sensor '{}': LAS stores the sample spacing in whole ps; "
            "detector.sample_rate_gsps {} gives {} ps",
            sensor.name, d.sample_rate_gsps, period_ps));
    las::WaveformPackets w;
    w.bits = d.bits <= 8 ? 8 : d.bits <= 16 ? 16 : 32;
    w.samples = o.waveform_samples;
    w.spacing_ps = static_cast<std::uint32_t>(std::round(period_ps));
    w.gain = 1.0 / d.gain_counts_per_pe;
    w.offset = -d.offset_counts / d.gain_counts_per_pe;
    w.external = o.wdp;
    return w;
}

// The LAS layout the options ask for; sets the job's waveform recording. The linear detector's
// echo fields (amplitude, width, deviation) go into extra bytes whenever it reports them.
las::LasWriterOptions writer_options(const Opts& o, Job& job) {
    las::LasWriterOptions lo;
    lo.point_format = static_cast<std::uint8_t>(o.format);
    lo.scale = o.scale;
    lo.file_source_id = job.sensor.point_source_id;
    const bool linear = job.sensor.detector == sensor::DetectorKind::Linear;
    lo.echo_fields = linear;
    const bool wave_format = o.format == 4 || o.format == 5 || o.format >= 9;
    if (!o.waveform && !wave_format) {
        if (o.wdp)
            throw mirage::ConfigError(
                "render: --wdp needs --waveform (or point format 4, 5, 9, 10)");
        return lo;
    }
    if (!linear)
        throw mirage::ConfigError("render --waveform: sensor '" + job.sensor.name +
                                  "' has no waveform digitiser (detector.kind: linear)");
    if (!wave_format)
        lo.point_format = static_cast<std::uint8_t>(o.format == 1   ? 4
                                                    : o.format == 3 ? 5
                                                    : o.format == 6 ? 9
                                                                    : 10);
    lo.waveform = packets(o, job.sensor);
    job.options.waveform_samples = o.waveform_samples;
    return lo;
}

}  // namespace

void register_render(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "render", "Render a scene with a sensor along a trajectory into a LAS file");
    auto opts = std::make_shared<Opts>();
    add_job_options(*cmd, opts->job);
    cmd->add_option("--out", opts->out, "Output LAS 1.4 file")->required();
    cmd->add_option("--format", opts->format,
                    "LAS point format: 1, 3, 6 or 7; with waveforms 4, 5, 9 or 10")
        ->check(CLI::IsMember({1, 3, 4, 5, 6, 7, 9, 10}))
        ->capture_default_str();
    cmd->add_flag("--waveform", opts->waveform,
                  "Record each pulse's digitised waveform (linear detector): point format 1, 3, "
                  "6, 7 becomes 4, 5, 9, 10");
    cmd->add_option("--waveform-samples", opts->waveform_samples,
                    "Samples recorded per pulse, from its first arrival")
        ->check(CLI::Range(1u, 65536u))
        ->capture_default_str();
    cmd->add_flag("--wdp", opts->wdp,
                  "Keep the waveform packets in an external .wdp file beside the LAS file");
    cmd->add_option("--scale", opts->scale, "LAS coordinate scale in metres")
        ->capture_default_str();
    cmd->callback([opts] {
        Job job = load_job(opts->job);
        std::fprintf(stderr, "%s", sensor::describe(job.sensor).c_str());
        las::LasWriterOptions lo = writer_options(*opts, job);
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
