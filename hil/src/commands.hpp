// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <CLI/CLI.hpp>

namespace mirage::hil {

// Each registers a subcommand on `app`; the callback returns the process exit code via throw
// CLI::RuntimeError(code) on failure.
void register_render(CLI::App& app);
void register_demo(CLI::App& app);
void register_bench(CLI::App& app);
void register_las_info(CLI::App& app);
void register_sensors(CLI::App& app);
void register_emulate(CLI::App& app);
void register_stream_bench(CLI::App& app);
void register_live(CLI::App& app);
void register_fake_ins(CLI::App& app);
void register_replay(CLI::App& app);
void register_record(CLI::App& app);
void register_rig(CLI::App& app);

}  // namespace mirage::hil
