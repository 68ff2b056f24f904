// SPDX-License-Identifier: Apache-2.0
#include "ouster_presets.hpp"

#include <array>
#include <cstddef>

#include "calibration_tables.hpp"

namespace mirage::sensor::detail {
namespace {

// OS-2-128 unit 992210000957 (FW 2.3.0), degrees: ouster-lidar/ouster-sdk @46b7bce
// tests/pcaps/OS-2-128-U1_v2.3.0_1024x10.json (the os2_128_rng19.json capture of
// docs/wire-formats.md §6). Row 0 = top beam.
constexpr std::array<double, 128> kOs2_128AltitudeDeg = {
    10.76, 10.58, 10.42, 10.24, 10.1,   9.93,   9.76,   9.57,   9.41,   9.24,   9.09,  8.91,  8.75,
    8.57,  8.41,  8.23,  8.08,  7.9,    7.74,   7.55,   7.39,   7.21,   7.03,   6.86,  6.7,   6.53,
    6.35,  6.18,  6.02,  5.83,  5.67,   5.5,    5.32,   5.14,   4.97,   4.81,   4.63,  4.46,  4.28,
    4.11,  3.95,  3.76,  3.58,  3.43,   3.24,   3.07,   2.9,    2.72,   2.55,   2.37,  2.21,  2.03,
    1.87,  1.69,  1.51,  1.32,  1.16,   0.98,   0.81,   0.63,   0.46,   0.29,   0.11,  -0.05, -0.25,
    -0.42, -0.58, -0.76, -0.93, -1.11,  -1.28,  -1.45,  -1.63,  -1.81,  -1.97,  -2.16, -2.32, -2.5,
    -2.68, -2.85, -3.02, -3.19, -3.37,  -3.55,  -3.73,  -3.9,   -4.07,  -4.25,  -4.4,  -4.58, -4.75,
    -4.94, -5.11, -5.28, -5.46, -5.64,  -5.8,   -5.96,  -6.15,  -6.32,  -6.49,  -6.66, -6.84, -7.0,
    -7.17, -7.35, -7.51, -7.69, -7.86,  -8.04,  -8.22,  -8.38,  -8.55,  -8.72,  -8.89, -9.06, -9.23,
    -9.4,  -9.57, -9.74, -9.91, -10.07, -10.24, -10.41, -10.58, -10.75, -10.92, -11.09};
constexpr std::array<double, 128> kOs2_128AzimuthDeg = {
    2.07,  0.66,  -0.71, -2.08, 2.07,  0.69,  -0.7,  -2.09, 2.06,  0.67,  -0.71, -2.06, 2.06,
    0.69,  -0.71, -2.07, 2.07,  0.69,  -0.71, -2.07, 2.07,  0.69,  -0.7,  -2.08, 2.05,  0.68,
    -0.69, -2.06, 2.06,  0.69,  -0.69, -2.07, 2.08,  0.69,  -0.69, -2.06, 2.08,  0.69,  -0.69,
    -2.07, 2.08,  0.69,  -0.69, -2.05, 2.08,  0.7,   -0.68, -2.06, 2.09,  0.7,   -0.67, -2.05,
    2.08,  0.7,   -0.68, -2.05, 2.08,  0.71,  -0.67, -2.06, 2.08,  0.71,  -0.68, -2.05, 2.07,
    0.71,  -0.67, -2.05, 2.08,  0.7,   -0.68, -2.05, 2.09,  0.71,  -0.66, -2.05, 2.09,  0.71,
    -0.67, -2.05, 2.09,  0.71,  -0.66, -2.05, 2.1,   0.71,  -0.66, -2.05, 2.09,  0.73,  -0.67,
    -2.05, 2.1,   0.72,  -0.66, -2.05, 2.09,  0.72,  -0.66, -2.05, 2.11,  0.73,  -0.69, -2.03,
    2.1,   0.72,  -0.65, -2.04, 2.11,  0.72,  -0.67, -2.05, 2.1,   0.72,  -0.66, -2.04, 2.11,
    0.72,  -0.66, -2.04, 2.1,   0.72,  -0.65, -2.03, 2.11,  0.73,  -0.66, -2.04};

constexpr int kProducts[] = {0, 1, 2};
constexpr int kBeams[] = {32, 64, 128};
constexpr int kColumns[] = {512, 1024, 2048};
constexpr int kRates[] = {10, 20};

std::string name_of(const OusterPresetSpec& s) {
    return "os" + std::to_string(s.product) + "-" + std::to_string(s.beams) + "-" +
           std::to_string(s.columns) + "x" + std::to_string(s.hz);
}

// Units without a published table: evenly spaced altitudes over the product's vertical field of
// view (OS0 90°, OS1 45°, OS2 22.5°; data sheets) and the staggered 4-beam azimuth pattern
// {3a, a, −a, −3a} of the real units (a = 1.055° on the gen-1 OS1, 0.69° on the OS2 capture;
// 2.11° assumed for the OS0). Plausible, not a real unit's calibration.
LaserSpec generated_beam(const OusterPresetSpec& s, int row) {
    const double half_fov = s.product == 0 ? 45.0 : s.product == 1 ? 22.5 : 11.25;
    const double a = s.product == 0 ? 2.11 : s.product == 1 ? 1.055 : 0.69;
    constexpr std::array<double, 4> kCycle = {3.0, 1.0, -1.0, -3.0};
    const double step = 2.0 * half_fov / double(s.beams - 1);
    return {half_fov - step * double(row), a * kCycle[static_cast<std::size_t>(row % 4)], 0.0};
}

}  // namespace

std::vector<std::string> ouster_preset_names() {
    std::vector<std::string> names;
    for (int p : kProducts)
        for (int h : kBeams)
            for (int w : kColumns)
                for (int f : kRates) names.push_back(name_of({p, h, w, f}));
    return names;
}

bool parse_ouster_preset(const std::string& name, OusterPresetSpec& out) {
    for (int p : kProducts)
        for (int h : kBeams)
            for (int w : kColumns)
                for (int f : kRates)
                    if (name == name_of({p, h, w, f})) {
                        out = {p, h, w, f};
                        return true;
                    }
    return false;
}

// Azimuth 360°·m/W + beam_azimuth_angles[r] clockwise (θ = −beam_az, docs/wire-formats.md §2.8):
// the FLU frame of the pattern is Ouster's *lidar* frame (column 0 along +x); Ouster's sensor frame
// is turned 180° about z.
SpinningConfig ouster_spinning_config(const OusterPresetSpec& s) {
    SpinningConfig c;
    c.sequence_period_ns = 1e9 / (double(s.columns) * s.hz);
    c.rotation_hz = s.hz;
    c.family = SpinningFamily::Ouster;
    for (int r = 0; r < s.beams; ++r) {
        const auto i = static_cast<std::size_t>(r);
        if (s.product == 1 && s.beams == 64) {
            c.lasers.push_back(
                {tables::kOs1Gen1AltitudeDeg[i], tables::kOs1Gen1AzimuthCycleDeg[i % 4], 0.0});
        } else if (s.product == 1 && s.beams == 128) {
            c.lasers.push_back(
                {tables::kOs1_128AltitudeDeg[i], tables::kOs1_128AzimuthDeg[i], 0.0});
        } else if (s.product == 2 && s.beams == 128) {
            c.lasers.push_back({kOs2_128AltitudeDeg[i], kOs2_128AzimuthDeg[i], 0.0});
        } else {
            c.lasers.push_back(generated_beam(s, r));
        }
    }
    return c;
}

}  // namespace mirage::sensor::detail
