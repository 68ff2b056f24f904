// SPDX-License-Identifier: Apache-2.0
// `--keep-awake` (docs/time.md §5) does something in every command that documents it: the run
// keeps the sending CPU awake and says so, and only when the run is paced (emulate
// --as-fast-as-possible and replay --top-speed have nothing to keep on time).
#include <gtest/gtest.h>
#include <sched.h>

#include <fstream>
#include <string>

#include "cli_run.hpp"
#include "live_yard.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

const std::string kNote = "kept out of idle (--keep-awake)";

// "mirage emulate: sending from CPU 1, kept …": the last CPU the command may run on (as this
// test).
std::string cpus_note(const char* command) {
    cpu_set_t set;
    CPU_ZERO(&set);
    sched_getaffinity(0, sizeof set, &set);
    int last = 0;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) last = c;
    return std::string("mirage ") + command + ": sending from CPU " + std::to_string(last) + ", " +
           kNote;
}

TEST(KeepAwakeCli, EveryPacedCommandKeepsTheSendingCpuAwake) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    const std::string emulate = "emulate --scene " + scene +
                                " --sensor vlp16 --sub-rays 1 --pose 0,0,2 --duration 0.5 "
                                "--no-status --to 127.0.0.1 --data-port 9 --position-port 0";
    const RunResult e = run_mirage(emulate + " --keep-awake");
    ASSERT_EQ(e.exit_code, 0) << e.output;
    EXPECT_NE(e.output.find(cpus_note("emulate")), std::string::npos) << e.output;
    const RunResult plain = run_mirage(emulate);
    EXPECT_EQ(plain.output.find(kNote), std::string::npos) << plain.output;

    const RunResult gen = run_mirage("emulate --scene " + scene +
                                     " --sensor vlp16 --sub-rays 1 --pose 0,0,2 --duration 0.3 "
                                     "--as-fast-as-possible --keep-awake --no-status --pcap " +
                                     tmp.file("c.pcap"));
    ASSERT_EQ(gen.exit_code, 0) << gen.output;
    EXPECT_EQ(gen.output.find(kNote), std::string::npos) << "nothing paced, nothing kept awake";
    const RunResult rp =
        run_mirage("replay " + tmp.file("c.pcap") + " --to 127.0.0.1 -q --keep-awake");
    ASSERT_EQ(rp.exit_code, 0) << rp.output;
    EXPECT_NE(rp.output.find(cpus_note("replay")), std::string::npos) << rp.output;

    {
        std::ofstream(tmp.file("rig.yaml"))
            << "scene: yard.yaml\nnavigation: {trajectory: 'static:2,-3,1.8,0,0,30'}\n"
               "duration: 0.5\nsensors:\n  - {name: a, sensor: vlp16, to: 127.0.0.1, ports: "
               "{data: 9, position: 0}}\n";
    }
    const RunResult rig = run_mirage("rig " + tmp.file("rig.yaml") + " --no-status --keep-awake");
    ASSERT_EQ(rig.exit_code, 0) << rig.output;
    EXPECT_NE(rig.output.find(cpus_note("rig")), std::string::npos) << rig.output;

    const RunResult live =
        run_mirage("live --scene " + scene + " --nav sbg-can:memory:ka --fake-ins " + traj +
                   " --sensor vlp16 --sub-rays 1 --duration 0.5 --no-status --position-port 0 "
                   "--to 127.0.0.1 --data-port 9 --keep-awake");
    ASSERT_EQ(live.exit_code, 0) << live.output;
    EXPECT_NE(live.output.find(cpus_note("live")), std::string::npos) << live.output;
}

}  // namespace
}  // namespace mirage::test
