// SPDX-License-Identifier: Apache-2.0
// `mirage`: one executable, one subcommand per job.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.hpp"
#include "mirage/core/error.hpp"

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
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const mirage::ConfigError& e) {
        std::fprintf(stderr, "mirage: configuration error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mirage: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
