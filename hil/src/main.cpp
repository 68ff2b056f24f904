// SPDX-License-Identifier: Apache-2.0
// `mirage`: one executable, one subcommand per job.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.hpp"
#include "mirage/core/error.hpp"

namespace {

bool known_command(CLI::App& app, const char* name) {
    for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->check_name(name)) return true;
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Mirage: real-time lidar emulator (Embree ray casting, seed-001 physics, LAS output)"};
    app.require_subcommand(1);
    mirage::hil::register_render(app);
    mirage::hil::register_demo(app);
    mirage::hil::register_bench(app);
    mirage::hil::register_las_info(app);
    mirage::hil::register_sensors(app);
    mirage::hil::register_emulate(app);
    mirage::hil::register_stream_bench(app);
    mirage::hil::register_live(app);
    mirage::hil::register_fake_ins(app);
    mirage::hil::register_replay(app);
    mirage::hil::register_record(app);
    mirage::hil::register_rig(app);
    if (argc > 1 && argv[1][0] != '-' && !known_command(app, argv[1])) {
        std::fprintf(stderr, "mirage: unknown command '%s' (mirage --help lists them)\n", argv[1]);
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {
        return e.get_exit_code();  // a command's own verdict (1: runtime failure)
    } catch (const CLI::ParseError& e) {
        // --help and --version print and exit 0; every other parse error is an argument error:
        // CLI11's message names the option, and the exit code is 2 like any configuration error
        // (docs/commands.md), not CLI11's own 100-range codes.
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    } catch (const mirage::ConfigError& e) {
        std::fprintf(stderr, "mirage: configuration error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mirage: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
