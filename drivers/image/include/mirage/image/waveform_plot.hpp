// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/image/png_writer.hpp"

namespace mirage::image {

// One pulse's recorded waveform and where its returns were detected.
struct WaveformPanel {
    std::vector<std::uint32_t> samples;  // digitiser counts
    std::vector<double> returns;         // in samples after the first (fractional)
};

// Panels stacked top to bottom, each `width` × `height` pixels on a white background: the
// samples as a dark line scaled to the panel's own min..max (a grey frame around it) and each
// return as a red vertical line. Samples are spread over the width, so every panel shows its
// whole window. ConfigError for no panels, an empty panel or a size outside [16, 4096].
RgbImage render_waveforms(const std::vector<WaveformPanel>& panels, int width = 800,
                          int height = 160);
void write_waveforms_png(const std::string& path, const std::vector<WaveformPanel>& panels,
                         int width = 800, int height = 160);

}  // namespace mirage::image
