// SPDX-License-Identifier: Apache-2.0
// `mirage las-info`: header summary, waveform records and every validation problem; exit 1 if
// any. Optionally a PNG of chosen pulses' recorded waveforms with their returns marked.
#include <fmt/format.h>

#include "commands.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_reader.hpp"
#include "waveform_preview.hpp"

namespace mirage::hil {
namespace {

struct LasInfoOpts {
    std::string path;
    std::string waveform_png;
    std::vector<std::uint64_t> points;
};

void print_header(const std::string& path, const las::LasHeaderInfo& h) {
    fmt::print(
        "{}: LAS {}.{}, point format {} ({} B), {} points (legacy {}), global encoding "
        "0x{:04x}\n",
        path, h.version_major, h.version_minor, h.point_format, h.record_length, h.point_count,
        h.legacy_point_count, h.global_encoding);
    fmt::print("  scale {} {} {}, offset {} {} {}\n", h.scale[0], h.scale[1], h.scale[2],
               h.offset[0], h.offset[1], h.offset[2]);
    fmt::print("  min {:.3f} {:.3f} {:.3f}, max {:.3f} {:.3f} {:.3f}\n", h.min[0], h.min[1],
               h.min[2], h.max[0], h.max[1], h.max[2]);
    fmt::print("  points by return:");
    for (int i = 0; i < 5; ++i) fmt::print(" {}", h.points_by_return[static_cast<std::size_t>(i)]);
    fmt::print("\n  CRS: {}\n", h.wkt.empty() ? "none" : h.wkt.substr(0, h.wkt.find(',')) + "…");
    if (!h.extra_bytes_names.empty())
        fmt::print("  extra bytes: {}\n", fmt::join(h.extra_bytes_names, ", "));
}

void print_waveforms(const las::LasFile& f) {
    const auto& h = f.header();
    if (h.wave_descriptors.empty()) return;
    std::uint64_t with = 0;
    for (const auto& p : f.points()) with += p.wave_index != 0;
    const char* where = (h.global_encoding & 2)   ? "in the file (EVLR)"
                        : (h.global_encoding & 4) ? "in the .wdp file"
                                                  : "nowhere (no global encoding bit)";
    fmt::print("  waveforms {}: {} of {} points have a packet\n", where, with, f.points().size());
    for (const auto& d : h.wave_descriptors)
        fmt::print(
            "  descriptor {}: {} bits, compression {}, {} samples every {} ps, value = {} + {} · "
            "sample\n",
            d.index, d.bits, d.compression, d.samples, d.spacing_ps, d.offset, d.gain);
}

}  // namespace

void register_las_info(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "las-info", "Print a LAS file's header and validate it (exit 1 on problems)");
    auto opts = std::make_shared<LasInfoOpts>();
    cmd->add_option("file", opts->path, "LAS file")->required()->check(CLI::ExistingFile);
    cmd->add_option("--waveform-png", opts->waveform_png,
                    "Draw chosen pulses' recorded waveforms, returns marked, into a PNG");
    cmd->add_option("--points", opts->points,
                    "Points whose waveforms --waveform-png draws (default: four with the most "
                    "returns)")
        ->delimiter(',');
    cmd->callback([opts] {
        const auto f = las::LasFile::read(opts->path);
        print_header(opts->path, f.header());
        print_waveforms(f);
        const auto problems = f.validate();
        for (const auto& p : problems) fmt::print("  PROBLEM: {}\n", p);
        if (!opts->waveform_png.empty())
            write_waveform_preview(opts->waveform_png, f, opts->points);
        if (!problems.empty()) throw CLI::RuntimeError(1);
        fmt::print("  valid\n");
    });
}

}  // namespace mirage::hil
