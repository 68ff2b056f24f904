// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdio>

#include "job.hpp"

namespace mirage::hil {

// The end-of-run summary: pulses, points, voids, misses, time, rates, × real time.
void print_summary(std::FILE* out, const char* what, const Job& job, const render::RenderStats& s);

}  // namespace mirage::hil
