// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/presets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {
namespace {

TEST(Presets, every_preset_constructs_with_unit_directions) {
    const auto names = preset_names();
    // 5 Velodyne, Ouster OS0/OS1/OS2 × 32/64/128 beams × 6 modes, 5 airborne, 3 arrays.
    EXPECT_EQ(names.size(), 5u + 3u * 3u * 6u + 5u + 3u);
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
    for (const auto& name : names) {
        const SensorModel m = preset(name);
        EXPECT_EQ(m.name, name);
        ASSERT_TRUE(m.scan) << name;
        EXPECT_GT(m.scan->channels(), 0u) << name;
        EXPECT_GT(m.scan->pulse_rate_hz(), 0.0) << name;
        EXPECT_EQ(m.point_source_id, 1) << name;
        // One sub-ray but for the full-waveform preset, whose footprint spreads its echoes.
        EXPECT_EQ(m.beam.sub_rays, name == "als-waveform" ? 19 : 1) << name;
        EXPECT_EQ(m.detector == DetectorKind::Linear, name == "als-waveform") << name;
        EXPECT_EQ(m.detector == DetectorKind::Geiger, name == "gmapd-32x32") << name;
        EXPECT_LT(m.receiver.min_range_m, m.receiver.max_range_m) << name;
        // A Geiger-mode detector times its events itself (no range noise).
        EXPECT_EQ(m.noise.range_sigma_m > 0.0, m.detector != DetectorKind::Geiger) << name;
        std::vector<PulseSpec> p(m.scan->group_size());
        m.scan->pulses(0, p.size(), p.data());
        for (const auto& s : p) EXPECT_NEAR(s.dir.norm(), 1.0, 1e-6) << name;
    }
    EXPECT_EQ(preset("vlp16").scan->channels(), 16u);
    EXPECT_EQ(preset("vlp32c").scan->channels(), 32u);
    EXPECT_EQ(preset("hdl32e").scan->channels(), 32u);
    EXPECT_EQ(preset("hdl64e-s3").scan->channels(), 64u);
    EXPECT_EQ(preset("os1-64-512x20").scan->channels(), 64u);
    EXPECT_EQ(preset("os1-128-2048x10").scan->channels(), 128u);
}

TEST(Presets, realistic_optics_per_family) {
    EXPECT_DOUBLE_EQ(preset("vlp16").beam.wavelength_m, 905e-9);
    EXPECT_DOUBLE_EQ(preset("os1-64-1024x10").beam.wavelength_m, 865e-9);
    EXPECT_DOUBLE_EQ(preset("vlp16").beam.divergence_rad, 3e-3);
    EXPECT_DOUBLE_EQ(preset("hdl64e-s3").beam.divergence_rad, 2e-3);
    EXPECT_DOUBLE_EQ(preset("vlp16").receiver.max_range_m, 100.0);
    EXPECT_DOUBLE_EQ(preset("hdl32e").receiver.max_range_m, 100.0);
    EXPECT_DOUBLE_EQ(preset("hdl64e-s3").receiver.max_range_m, 120.0);
    EXPECT_DOUBLE_EQ(preset("vlp32c").receiver.max_range_m, 200.0);
    EXPECT_DOUBLE_EQ(preset("os1-128-512x10").receiver.max_range_m, 120.0);
    EXPECT_FALSE(preset("vlp16").airborne);
}

TEST(Presets, a_10_percent_target_at_max_range_gives_a_few_hundred_electrons) {
    for (const auto& name : preset_names()) {
        const SensorModel m = preset(name);
        if (m.array.on()) continue;  // photon-starved by design (array_test.cpp)
        const double n = lambertian_electrons(m.beam, m.receiver, 0.1, m.receiver.max_range_m);
        std::printf("  %-16s %6.2f uJ  %6.0f m  %5.0f e-\n", name.c_str(),
                    m.beam.pulse_energy_j * 1e6, m.receiver.max_range_m, n);
        EXPECT_GT(n, 200.0) << name;
        EXPECT_LT(n, 800.0) << name;
        // Detector noise floor (eq. 12, first term) tuned to 10 e⁻ per unit normal.
        EXPECT_NEAR(
            m.receiver.noise_irradiance_sigma / noise_sigma_for_floor(1.0, m.beam, m.receiver),
            10.0, 1e-9)
            << name;
        // The pixel IFOV holds the spot: Ω_pix ≥ Ω_spot.
        const double f = m.receiver.f_number * m.receiver.aperture_diameter_m;
        const double omega_pix = m.receiver.detector_area_m2 / (f * f);
        const double omega_spot = M_PI * std::pow(m.beam.divergence_rad / 2, 2);
        EXPECT_GT(omega_pix, omega_spot) << name;
    }
    // Hand check of the VLP-16 comment: 0.1 µJ, 25 mm, 100 m, η 0.7 → 358.8 e⁻.
    const auto v = preset("vlp16");
    EXPECT_NEAR(lambertian_electrons(v.beam, v.receiver, 0.1, 100.0), 358.8, 0.1);
}

TEST(Presets, unknown_name_lists_the_known_ones) {
    try {
        preset("vlp17");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("unknown preset 'vlp17'"), std::string::npos) << what;
        EXPECT_NE(what.find("hdl64e-s3"), std::string::npos) << what;
        EXPECT_NE(what.find("os1-128-2048x20"), std::string::npos) << what;
    }
}

TEST(Presets, describe_prints_effective_values_for_every_channel) {
    const std::string d = describe(preset("vlp16"));
    EXPECT_NE(d.find("sensor 'vlp16': spinning, 16 channel(s), 289352 pulses/s"), std::string::npos)
        << d;
    EXPECT_NE(d.find("600.0 rpm"), std::string::npos) << d;
    EXPECT_NE(d.find("azimuth step 0.19907 deg"), std::string::npos) << d;
    EXPECT_NE(d.find("ch  15: elev   15.000 deg"), std::string::npos) << d;
    std::printf("%s", d.c_str());
    const std::string a = describe(preset("als-mirror"));
    EXPECT_NE(a.find("scan: sawtooth 500.0 kHz, scan rate 50.00 Hz (100.0 lines/s), fov 40.00 deg"),
              std::string::npos)
        << a;
}

}  // namespace
}  // namespace mirage::sensor
