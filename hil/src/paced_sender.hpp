// SPDX-License-Identifier: Apache-2.0
// The one sending thread of a real-time command (emulate, live, rig): packets are handed to it
// ahead of their send times and it sends each at its deadline, so rendering and encoding never
// delay a send (docs/rig.md §2, docs/benchmarks.md §3.1).
#pragma once
#include <memory>

#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/udp/shared_sender.hpp"

namespace mirage::hil {

// SCHED_FIFO at rt_priority when > 0, pinned to the CPU `awake` keeps out of idle when given;
// a refusal of either is reported on stderr as "mirage <command>: sender: ..." and the thread
// runs without it.
std::shared_ptr<udp::SharedSender> make_paced_sender(int rt_priority,
                                                     const hostclock::KeepAwake* awake,
                                                     const char* command);

}  // namespace mirage::hil
