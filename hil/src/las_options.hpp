// SPDX-License-Identifier: Apache-2.0
// The LAS layout a render asks for (`mirage render`, `mirage demo`): point format, scale, and
// with a waveform digitiser the echo fields and recorded waveforms (docs/file-formats.md §6.1).
#pragma once
#include <cstdint>

#include "job.hpp"
#include "mirage/las/las_writer.hpp"

namespace mirage::hil {

struct LasChoice {
    int format = 6;
    double scale = 0.001;
    bool waveform = false;  // record waveforms (formats 1, 3, 6, 7 become 4, 5, 9, 10)
    std::uint32_t waveform_samples = 256;
    bool wdp = false;  // packets in a .wdp beside the file
};

// The writer's options; sets the job's waveform recording. The linear detector's echo fields
// (amplitude, width, deviation) go into extra bytes whenever it reports them. ConfigError for a
// choice the sensor cannot make (waveforms without a digitiser, a clock not in whole ps, --wdp
// without waveforms).
las::LasWriterOptions writer_options(const LasChoice& choice, Job& job);

}  // namespace mirage::hil
