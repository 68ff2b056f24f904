// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/core/time.hpp"

namespace mirage::core {

// One lidar return as produced by the pipeline and consumed by every output (LAS, packets).
// Position is in the scene's local frame (double); add Georef::anchor() for world coordinates.
struct PointRecord {
    double x = 0, y = 0, z = 0;   // local frame, m
    GpsTime t{};                  // firing time of the pulse
    std::uint64_t pulse = 0;      // global pulse index
    float range_m = 0;            // measured range (with noise)
    float scan_angle_deg = 0;     // LAS scan angle: off-nadir / elevation, degrees
    float azimuth_deg = 0;        // sensor-frame azimuth, clockwise from +x, [0, 360)
    float amplitude = 0;          // waveform detector: echo peak above baseline, counts (else 0)
    double n_laser = 0;           // photo-electrons of the return (before calibration)
    std::uint16_t intensity = 0;  // calibrated, 0..65535
    std::uint16_t channel = 0;    // laser / beam index
    std::uint16_t point_source_id = 0;
    std::uint16_t red = 0, green = 0, blue = 0;
    std::uint8_t return_number = 1;  // 1-based
    std::uint8_t number_of_returns = 1;
    std::uint8_t classification = 1;  // LAS class (1 = unclassified)
    std::uint8_t scan_direction = 0;  // LAS scan direction flag
    std::uint8_t edge_of_flight_line = 0;
    float echo_width_ns = 0;  // waveform detector: the echo's fitted Gaussian σ (else 0)
    float deviation = 0;      // and the fit's RMS residual over the echo's samples, counts
    // A render recording waveforms (docs/time-resolved.md §13): the pulse's digitised samples
    // start at index `wave` of the chunk's samples (kNoWave: none recorded for this return), and
    // the echo lies wave_location_ps after the first of them.
    std::uint32_t wave = kNoWave;
    float wave_location_ps = 0;
    float beam_dx = 0, beam_dy = 0, beam_dz = 0;  // waveform detector: the beam's unit direction
    std::uint32_t pixel = 0;  // an array sensor's pixel (column + row · columns), else 0
    // A Geiger-mode detector's photon event: 1 signal, 2 background or dark, 3 afterpulse,
    // 4 crosstalk (docs/photon-counting.md §4); 0 for any other detector's return.
    std::uint8_t event = 0;
    static constexpr std::uint32_t kNoWave = 0xFFFFFFFFu;
};

}  // namespace mirage::core
