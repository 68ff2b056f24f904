// SPDX-License-Identifier: Apache-2.0
// `--keep-awake` (docs/time.md §5) does something in every command that documents it: the run
// keeps the sending CPU awake and says so, and only when the run is paced (emulate
// --as-fast-as-possible and replay --top-speed have nothing to keep on time).
#include <gtest/gtest.h>
#include <sched.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "live_yard.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

const std::string kNote = "kept out of idle (--keep-awake)";

// The last CPU this test may run on (the one a command's sender takes).
int last_cpu() {
    cpu_set_t set;
    CPU_ZERO(&set);
    sched_getaffinity(0, sizeof set, &set);
    int last = 0;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &set)) last = c;
    return last;
}

// "mirage emulate: sending from CPU 1, kept …": that CPU.
std::string cpus_note(const char* command) {
    return std::string("mirage ") + command + ": sending from CPU " + std::to_string(last_cpu()) +
           ", " + kNote;
}

// A thread of a running process: its scheduling policy (field 41 of its stat) and the CPUs it
// may run on (Cpus_allowed_list of its status).
struct ThreadInfo {
    int policy = -1;
    std::string cpus;
};

std::vector<ThreadInfo> threads_of(int pid) {
    std::vector<ThreadInfo> out;
    std::error_code ec;
    const std::string task = "/proc/" + std::to_string(pid) + "/task";
    for (const auto& t : std::filesystem::directory_iterator(task, ec)) {
        ThreadInfo info;
        std::string stat;
        std::getline(std::ifstream(t.path() / "stat"), stat);
        std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // from field 3, the state
        std::string f;
        for (int k = 3; k <= 41 && fields >> f; ++k)
            if (k == 41) info.policy = std::stoi(f);
        std::ifstream status(t.path() / "status");
        for (std::string line; std::getline(status, line);)
            if (line.rfind("Cpus_allowed_list:", 0) == 0)
                info.cpus = line.substr(line.find_first_not_of(" \t", 18));
        out.push_back(info);
    }
    return out;
}

// What the note says is so: while emulate runs with --keep-awake, one thread is pinned to the
// sending CPU at SCHED_IDLE (the spinner) and another is pinned there at its normal policy (the
// sender).
TEST(KeepAwakeCli, TheSenderAndItsSpinnerArePinnedToTheSendingCpu) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml");
    { std::ofstream(scene) << kScene; }
    BackgroundMirage b;
    b.pipe = ::popen(("echo pid $$; exec " + std::string(MIRAGE_EXE) + " emulate --scene " + scene +
                      " --sensor vlp16 --sub-rays 1 --pose 0,0,2 --duration 2 --no-status "
                      "--to 127.0.0.1 --data-port 9 --position-port 0 --keep-awake 2>&1")
                         .c_str(),
                     "r");
    std::smatch m;
    const std::string first = b.wait_for(std::regex("^pid "));
    ASSERT_TRUE(std::regex_search(first, m, std::regex("pid ([0-9]+)"))) << b.output;
    const int pid = std::stoi(m[1]);
    ASSERT_FALSE(b.wait_for(std::regex("kept out of idle")).empty()) << b.output;
    const std::string cpu = std::to_string(last_cpu());
    bool spinner = false, sender = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!(spinner && sender) && std::chrono::steady_clock::now() < deadline) {
        for (const ThreadInfo& t : threads_of(pid)) {
            if (t.cpus != cpu) continue;
            (t.policy == SCHED_IDLE ? spinner : sender) = true;
        }
    }
    EXPECT_TRUE(spinner) << "no SCHED_IDLE thread pinned to CPU " << cpu;
    EXPECT_TRUE(sender) << "no other thread pinned to CPU " << cpu;
    EXPECT_EQ(b.finish(), 0) << b.output;
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
