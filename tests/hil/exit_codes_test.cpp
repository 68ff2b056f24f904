// SPDX-License-Identifier: Apache-2.0
// Every command's exit codes as docs/commands.md promises: 0 for --help, 2 for any argument or
// configuration error (with a message naming the option, key or input), 1 for a failure while
// running.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

struct Case {
    std::string args;
    int code;
    std::string names;  // text the message must contain
};

struct Command {
    std::string name;
    std::vector<Case> cases;
};

std::vector<Command> commands(const TempDir& tmp) {
    const std::string junk = tmp.file("junk.bin");
    std::ofstream(junk) << "not a capture, not a LAS file";
    const std::string las = tmp.file("a.las");
    // A sensor 20 km from its scene's anchor: another frame than the scene's (exit 2).
    const std::string plane = tmp.file("plane.yaml"), far_rig = tmp.file("far.yaml");
    std::ofstream(plane) << "materials:\n  m: {reflectance: 0.5}\nobjects:\n"
                            "  - {type: plane, material: m, size: [80, 80]}\n";
    std::ofstream(far_rig)
        << "scene: plane.yaml\nnavigation: {trajectory: 'static:0,20000,2'}\n"
           "duration: 1\nsensors:\n"
           "  - {name: far, sensor: vlp16, to: 127.0.0.1, ports: {data: 2368}}\n";
    return {
        {"render",
         {{"--out " + las + " --bogus", 2, "--bogus"},
          {"--out " + las + " --threads abc", 2, "--threads"},
          {"--out " + las + " --sensor no-such-sensor", 2, "no-such-sensor"},
          {"--out " + las + " --cn2 strong", 2, "--cn2"},
          {"--out " + las + " --cn2 1", 2, "--cn2"},
          {"--out " + las + " --pulses-per-cell 60", 2, "--pulses-per-cell"},
          {"--out /dev/null/x.las --duration 0.05", 1, "/dev/null/x.las"}}},
        {"demo",
         {{"--bogus", 2, "--bogus"},
          {"--seed abc", 2, "--seed"},
          {"--photon-seconds abc", 2, "--photon-seconds"},
          {"--out-dir /dev/null/x", 1, "/dev/null/x"}}},
        {"bench",
         {{"--bogus", 2, "--bogus"},
          {"--threads x", 2, "--threads"},
          {"--quick --out-dir /dev/null/x", 1, "/dev/null/x"}}},
        {"las-info",
         {{"--bogus " + junk, 2, "--bogus"},
          {tmp.file("missing.las"), 2, "missing.las"},
          {junk, 1, "junk.bin"}}},
        {"sensors", {{"--bogus", 2, "--bogus"}, {"no-such-preset", 2, "no-such-preset"}}},
        {"emulate",
         {{"--bogus", 2, "--bogus"},
          {"--sensor vlp16 --rpm abc --pcap x.pcap", 2, "--rpm"},
          {"--sensor als-mirror --pose 0,0,1 --pcap x.pcap", 2, "als-mirror"},
          {"--scene " + plane + " --sensor vlp16 --pose 0,20000,2 --pcap x.pcap", 2,
           "from the scene's anchor"},
          {"--sensor vlp16 --pose 0,0,1 --duration 0.05 --as-fast-as-possible --pcap "
           "/dev/null/x.pcap",
           1, "/dev/null/x.pcap"}}},
        {"stream-bench", {{"--bogus", 2, "--bogus"}, {"--seconds abc", 2, "--seconds"}}},
        {"rig", {{"--bogus " + far_rig, 2, "--bogus"}, {far_rig, 2, "sensors[0] ('far'"}}},
        {"live",
         {{"--nav nmea:/dev/null/x --sensor vlp16 --bogus", 2, "--bogus"},
          {"--nav bogus:x --sensor vlp16", 2, "bogus"},
          {"--nav nmea:/dev/null/x --sensor vlp16 --duration 0.1", 1, "/dev/null/x"}}},
        {"fake-ins",
         {{"--bogus", 2, "--bogus"},
          {"--trajectory demo-car --protocol nope --to pty", 2, "nope"},
          {"--trajectory demo-car --protocol nmea --to pty:/dev/null/x --duration 0.1", 1,
           "/dev/null/x"}}},
        {"replay",
         {{"--bogus " + junk + " --to 127.0.0.1", 2, "--bogus"},
          {tmp.file("missing.pcap") + " --to 127.0.0.1", 2, "missing.pcap"},
          {"--speed -1 " + junk + " --to 127.0.0.1", 2, "--speed"},
          {junk + " --to 127.0.0.1", 1, "junk.bin"}}},
        {"record",
         {{"--out x.pcap --listen :0 --bogus", 2, "--bogus"},
          {"--out x.pcap --listen abc", 2, "--listen"},
          {"--out /dev/null/x.pcap --listen :0 --duration 0.1", 1, "/dev/null/x.pcap"}}},
    };
}

TEST(ExitCodes, help_exits_0_and_every_error_exits_as_documented) {
    TempDir tmp;
    for (const auto& cmd : commands(tmp)) {
        const auto help = run_mirage(cmd.name + " --help");
        EXPECT_EQ(help.exit_code, 0) << cmd.name;
        EXPECT_NE(help.output.find("Usage"), std::string::npos) << cmd.name << ": " << help.output;
        for (const auto& c : cmd.cases) {
            const auto r = run_mirage(cmd.name + " " + c.args);
            EXPECT_EQ(r.exit_code, c.code) << "mirage " << cmd.name << " " << c.args << "\n"
                                           << r.output;
            EXPECT_NE(r.output.find(c.names), std::string::npos)
                << "mirage " << cmd.name << " " << c.args << ": the message does not name '"
                << c.names << "'\n"
                << r.output;
        }
    }
}

TEST(ExitCodes, no_or_unknown_command_is_an_argument_error) {
    EXPECT_EQ(run_mirage("").exit_code, 2);
    const auto r = run_mirage("no-such-command");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.output.find("no-such-command"), std::string::npos) << r.output;
    EXPECT_EQ(run_mirage("--help").exit_code, 0);
}

}  // namespace
}  // namespace mirage::test
