// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdio>

#include "job.hpp"
#include "mirage/hostclock/clock_step.hpp"

namespace mirage::hil {

// The end-of-run summary: pulses, points, voids, misses, time, rates, × real time.
void print_summary(std::FILE* out, const char* what, const Job& job, const render::RenderStats& s);
// "  followed N step(s) of the host clock: timestamps +X s" when there were any (docs/time.md §1).
void print_clock_steps(std::FILE* out, const hostclock::ClockStepFollower* clock);

}  // namespace mirage::hil
