// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

#include "mirage/sensor/spinning.hpp"

namespace mirage::sensor::detail {

// An Ouster preset name "os<P>-<H>-<W>x<F>": product line P ∈ {0, 1, 2}, H ∈ {32, 64, 128}
// beams, W ∈ {512, 1024, 2048} columns per frame, F ∈ {10, 20} Hz.
struct OusterPresetSpec {
    int product = 1;
    int beams = 64;
    int columns = 1024;
    int hz = 10;
};

std::vector<std::string> ouster_preset_names();
bool parse_ouster_preset(const std::string& name, OusterPresetSpec& out);
// Beam table and column timing: every beam of a column fires at the column time, period 1/(W·F).
SpinningConfig ouster_spinning_config(const OusterPresetSpec& spec);

}  // namespace mirage::sensor::detail
