// SPDX-License-Identifier: Apache-2.0
// `mirage las-info`: header summary and every validation problem; exit 1 if any.
#include <fmt/format.h>

#include "commands.hpp"
#include "mirage/las/las_reader.hpp"

namespace mirage::hil {

void register_las_info(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "las-info", "Print a LAS file's header and validate it (exit 1 on problems)");
    auto path = std::make_shared<std::string>();
    cmd->add_option("file", *path, "LAS file")->required()->check(CLI::ExistingFile);
    cmd->callback([path] {
        const auto f = las::LasFile::read(*path);
        const auto& h = f.header();
        fmt::print(
            "{}: LAS {}.{}, point format {} ({} B), {} points (legacy {}), global encoding "
            "0x{:04x}\n",
            *path, h.version_major, h.version_minor, h.point_format, h.record_length, h.point_count,
            h.legacy_point_count, h.global_encoding);
        fmt::print("  scale {} {} {}, offset {} {} {}\n", h.scale[0], h.scale[1], h.scale[2],
                   h.offset[0], h.offset[1], h.offset[2]);
        fmt::print("  min {:.3f} {:.3f} {:.3f}, max {:.3f} {:.3f} {:.3f}\n", h.min[0], h.min[1],
                   h.min[2], h.max[0], h.max[1], h.max[2]);
        fmt::print("  points by return:");
        for (int i = 0; i < 5; ++i)
            fmt::print(" {}", h.points_by_return[static_cast<std::size_t>(i)]);
        fmt::print("\n  CRS: {}\n",
                   h.wkt.empty() ? "none" : h.wkt.substr(0, h.wkt.find(',')) + "…");
        const auto problems = f.validate();
        for (const auto& p : problems) fmt::print("  PROBLEM: {}\n", p);
        if (!problems.empty()) throw CLI::RuntimeError(1);
        fmt::print("  valid\n");
    });
}

}  // namespace mirage::hil
