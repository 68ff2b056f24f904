// SPDX-License-Identifier: Apache-2.0
// `mirage sensors`: list presets, or describe one (effective per-channel configuration).
#include <cstdio>

#include "commands.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::hil {

void register_sensors(CLI::App& app) {
    auto* cmd =
        app.add_subcommand("sensors", "List sensor presets, or describe one preset or YAML file");
    auto name = std::make_shared<std::string>();
    cmd->add_option("sensor", *name, "Preset name or sensor YAML to describe");
    cmd->callback([name] {
        if (name->empty()) {
            for (const auto& n : sensor::preset_names()) std::printf("%s\n", n.c_str());
            return;
        }
        std::printf("%s", sensor::describe(sensor::resolve_sensor(*name)).c_str());
    });
}

}  // namespace mirage::hil
