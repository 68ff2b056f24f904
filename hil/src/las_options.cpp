// SPDX-License-Identifier: Apache-2.0
#include "las_options.hpp"

#include <fmt/format.h>

#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::hil {
namespace {

// Waveform packets as the digitiser makes them (docs/file-formats.md §6.1): its bits rounded up
// to a byte multiple, its clock in whole ps, and gain and offset that turn stored counts into
// photo-electrons.
las::WaveformPackets packets(const LasChoice& o, const sensor::SensorModel& sensor) {
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

}  // namespace

las::LasWriterOptions writer_options(const LasChoice& o, Job& job) {
    las::LasWriterOptions lo;
    lo.point_format = static_cast<std::uint8_t>(o.format);
    lo.scale = o.scale;
    lo.file_source_id = job.sensor.point_source_id;
    const bool linear = job.sensor.detector == sensor::DetectorKind::Linear;
    lo.echo_fields = linear;
    lo.event_fields = job.sensor.detector == sensor::DetectorKind::Geiger || job.sensor.array.on();
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

}  // namespace mirage::hil
