// SPDX-License-Identifier: Apache-2.0
// `mirage bench`, run time against error: VLP-16 renders of the demo drive at several sub-ray
// counts against a denser reference, and the BVH qualities' build and render times.
#pragma once
#include <memory>

#include "bench_report.hpp"
#include "job.hpp"

namespace mirage::hil {

// The demo town and the job inputs every bench render starts from.
struct BenchBase {
    std::shared_ptr<const scene::Scene> town;
    double scene_seconds = 0;
    JobInputs inputs;
};

// Adds the error rows (1, 7 and 19 sub-rays against 37; 37 against 61) and the BVH rows
// (--quick: medium only) to `report`.
void bench_errors(const BenchBase& base, bool quick, BenchReport& report);

}  // namespace mirage::hil
