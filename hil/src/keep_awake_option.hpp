// SPDX-License-Identifier: Apache-2.0
// `--keep-awake` of the real-time commands (emulate, live, rig, replay): the sending thread runs
// on one CPU that a SCHED_IDLE spinner keeps out of idle for the run, so its timer wake-ups come
// on time (docs/time.md §5).
#pragma once
#include <memory>

#include "mirage/hostclock/keep_awake.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace mirage::hil {

void add_keep_awake_flag(CLI::App& cmd, bool& flag);
// Started when `on` on hostclock::sending_cpu() (a note on stderr names it, and any warning);
// null otherwise. The caller pins its sending thread to hostclock::sending_cpu_of(awake).
std::unique_ptr<hostclock::KeepAwake> keep_cpus_awake(bool on, const char* command);

}  // namespace mirage::hil
