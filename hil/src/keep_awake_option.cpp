// SPDX-License-Identifier: Apache-2.0
#include "keep_awake_option.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <vector>

namespace mirage::hil {

void add_keep_awake_flag(CLI::App& cmd, bool& flag) {
    cmd.add_flag("--keep-awake", flag,
                 "Run the sending thread on one CPU and keep that CPU out of idle (a SCHED_IDLE "
                 "spinner): its timer wake-ups come on time, but the CPU reads 100 % busy; "
                 "docs/time.md §5");
}

std::unique_ptr<hostclock::KeepAwake> keep_cpus_awake(bool on, const char* command) {
    if (!on) return nullptr;
    const int cpu = hostclock::sending_cpu();
    auto awake = std::make_unique<hostclock::KeepAwake>(std::vector<int>{cpu});
    std::fprintf(stderr, "mirage %s: sending from CPU %d, kept out of idle (--keep-awake)%s%s\n",
                 command, cpu, awake->warning().empty() ? "" : ": ", awake->warning().c_str());
    return awake;
}

}  // namespace mirage::hil
