// SPDX-License-Identifier: Apache-2.0
// Focal-plane arrays in the sensor model (docs/photon-counting.md §3): pixel-pulses in order,
// their lines of sight, the laser's share per pixel, the YAML keys and their errors.
#include "mirage/sensor/array.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"
#include "mirage/sensor/presets.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {
namespace {

std::string nadir_array_yaml(const std::string& extra = "") {
    return "base: als-mirror-sine\n"
           "beam: {divergence_mrad: 4}\n"
           "array: {columns: 32, rows: 32, pitch_um: 50, focal_length_mm: 400, fill_factor: 0.6" +
           extra + "}\n";
}

TEST(Array, pixel_pulses_follow_the_laser_in_order) {
    const auto m = load_sensor_yaml_text(nadir_array_yaml(), "a.yaml");
    ASSERT_TRUE(m.array.on());
    const auto& scan = dynamic_cast<const ArrayScan&>(*m.scan);
    EXPECT_EQ(m.scan->pulse_rate_hz(), scan.laser().pulse_rate_hz() * 1024);
    EXPECT_EQ(m.scan->group_size(), 1024u);
    std::vector<PulseSpec> px(3 * 1024), laser(3);
    m.scan->pulses(1024 * 5, px.size(), px.data());
    scan.laser().pulses(5, 3, laser.data());
    for (std::size_t k = 0; k < px.size(); ++k) {
        const PulseSpec& l = laser[k / 1024];
        ASSERT_EQ(px[k].pixel, k % 1024);
        ASSERT_EQ(px[k].t_ns, l.t_ns);
        // The pixel's angle from the laser's direction is its tangent's (the array turns rigidly).
        const double tx = (double(k % 32) - 15.5) * 50e-6 / 0.4;
        const double ty = (double(k % 1024 / 32) - 15.5) * 50e-6 / 0.4;
        const double want = std::atan(std::sqrt(tx * tx + ty * ty));
        const Eigen::Vector3d a = px[k].dir.cast<double>(), b = l.dir.cast<double>();
        const double got = std::atan2(a.cross(b).norm(), a.dot(b));
        ASSERT_NEAR(got, want, 2e-6) << k;
    }
    // An odd start inside a frame gives the same pixel-pulses.
    std::vector<PulseSpec> part(100);
    m.scan->pulses(1024 * 5 + 700, part.size(), part.data());
    for (std::size_t k = 0; k < part.size(); ++k) {
        ASSERT_EQ(part[k].pixel, px[700 + k].pixel);
        ASSERT_EQ(part[k].dir, px[700 + k].dir);
    }
}

// Nadir: columns across track (−y, right of the flight line), rows along it (−x, aft).
TEST(Array, nadir_columns_run_across_track) {
    const auto m = load_sensor_yaml_text(nadir_array_yaml(), "a.yaml");
    const auto& scan = dynamic_cast<const ArrayScan&>(*m.scan);
    // Find a laser pulse at nadir (the sine scan's middle) and compare its corner pixels.
    PulseSpec l;
    std::uint64_t k = 0;
    for (;; ++k) {
        scan.laser().pulses(k, 1, &l);
        if (std::abs(l.dir.y()) < 2e-3) break;
    }
    std::vector<PulseSpec> px(1024);
    m.scan->pulses(k * 1024, 1024, px.data());
    EXPECT_LT(px[31].dir.y(), px[0].dir.y());       // last column: further right (−y)
    EXPECT_LT(px[31 * 32].dir.x(), px[0].dir.x());  // last row: further aft (−x)
}

TEST(Array, gaussian_flash_shares_integrate_the_profile) {
    ArrayParams a;
    a.columns = 64;
    a.rows = 64;
    a.pitch_m = 50e-6;
    a.focal_length_m = 0.1;         // 0.5 mrad pixels, ±16 mrad field
    a.laser_divergence_rad = 8e-3;  // w = 4 mrad: the field holds ±4 w
    a.laser_profile = BeamProfile::Gaussian;
    const auto share = pixel_shares(a);
    double sum = 0;
    for (float s : share) sum += s;
    EXPECT_NEAR(sum, 1.0, 1e-6);
    // The centre four pixels: ¼·erf(√2·0.5/4)²·4 of the energy.
    const double c = std::erf(std::numbers::sqrt2 * 0.5 / 4.0);
    const double centre =
        share[31 * 64 + 31] + share[31 * 64 + 32] + share[32 * 64 + 31] + share[32 * 64 + 32];
    EXPECT_NEAR(centre, c * c, 1e-6);
    a.laser_profile = BeamProfile::TopHat;
    for (float s : pixel_shares(a)) ASSERT_FLOAT_EQ(s, 1.0f / 4096);
}

TEST(Array, flash_pixel_pulse_lights_the_pixel_square) {
    const auto m = load_sensor_yaml_text(nadir_array_yaml(", illumination: flash"), "a.yaml");
    const double ifov = 50e-6 / 0.4;
    const double t = std::tan(0.5 * m.beam.divergence_rad);
    EXPECT_NEAR(std::numbers::pi * t * t, ifov * ifov, 1e-15);
    EXPECT_EQ(m.beam.profile, BeamProfile::TopHat);
    EXPECT_NEAR(m.array.laser_divergence_rad, 4e-3, 1e-12);
    EXPECT_NEAR(m.receiver.f_number * m.receiver.aperture_diameter_m, 0.4, 1e-12);
    EXPECT_NEAR(m.receiver.detector_area_m2, 50e-6 * 50e-6 * 0.6, 1e-18);
    const auto b = load_sensor_yaml_text(nadir_array_yaml(", illumination: beamlets"), "b.yaml");
    EXPECT_NEAR(b.beam.divergence_rad, 4e-3, 1e-12);  // each beamlet keeps the beam's divergence
    for (float s : b.array.share) ASSERT_FLOAT_EQ(s, 1.0f / 1024);
    EXPECT_NE(describe(m).find("array: 32 x 32 pixels"), std::string::npos);
}

TEST(Array, yaml_errors_name_the_key) {
    const auto fails = [](const std::string& yaml, const std::string& what) {
        try {
            load_sensor_yaml_text(yaml, "bad.yaml");
            ADD_FAILURE() << "accepted: " << yaml;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos)
                << e.what() << " | " << what;
        }
    };
    fails("base: vlp16\narray: {rows: 4}\n", "array.columns: required");
    fails("base: vlp16\narray: {columns: 0, rows: 4}\n", "array.columns: 0 is outside");
    fails("base: vlp16\narray: {columns: 4, rows: 4, fill_factor: 1.5}\n", "array.fill_factor");
    fails("base: vlp16\narray: {columns: 4, rows: 4, illumination: laser}\n",
          "array.illumination: 'laser' is not flash or beamlets");
    fails("base: vlp16\nreceiver: {f_number: 2}\narray: {columns: 4, rows: 4}\n",
          "receiver.f_number: set by the array");
    fails("base: vlp16\narray: {columns: 4000, rows: 4000, focal_length_mm: 1}\n",
          "array.focal_length_mm: field of view");
    fails("base: vlp16\ndetector: {type: linear, dead_time_ns: 3}\n",
          "detector.dead_time_ns: only with detector.type: geiger");
    fails("base: vlp16\ndetector: {type: geiger, bits: 8}\n",
          "detector.bits: only with detector.type: linear");
    fails("base: vlp16\ndetector: {type: geiger, paralyzable: maybe}\n",
          "detector.paralyzable: 'maybe' is not true or false");
    fails("base: vlp16\ndetector: {type: geiger, afterpulse_probability: 1.5}\n",
          "detector.afterpulse_probability: 1.5 is outside [0, 1]");
    fails("base: gmapd-32x32\ndetector: {crosstalk_probability: -0.1}\n",
          "detector.crosstalk_probability: -0.1 is outside [0, 1]");
    fails("base: gmapd-32x32\narray: {columns: 100000}\n", "array.columns: 100000 is outside");
    // 20 kHz: a pulse every 50 µs; the gate from 1 100 m closes at 9.34 µs.
    fails("base: gmapd-32x32\nreceiver: {max_range_m: 8000}\n",
          "receiver.max_range_m: the gate closes 53.3703 µs after the pulse, past the next one "
          "(every 50 µs)");
    fails("base: gmapd-32x32\ndetector: {dead_time_ns: 48000}\n",
          "detector.dead_time_ns: a pixel firing at the gate's close would still be dead");
    fails("base: vlp16\ndetector: {type: geiger, free_running: true}\n",
          "detector.free_running: only for an array");
    fails(
        "base: vlp16\ndetector: {type: geiger, free_running: true}\narray: {columns: 2, rows: 2}\n",
        "detector.free_running: only for a laser firing at a fixed rate");
    fails("base: gmapd-32x32\ndetector: {free_running: perhaps}\n",
          "detector.free_running: 'perhaps' is not true or false");
}

// A free-running array carries its dead time across pulses: one longer than the gap between
// gates, or than the pulse period, is accepted (docs/photon-counting.md §2.1).
TEST(Array, a_free_running_array_takes_a_dead_time_past_the_next_gate) {
    const auto m = load_sensor_yaml_text(
        "base: gmapd-32x32\ndetector: {dead_time_ns: 60000, free_running: true}\n", "f.yaml");
    EXPECT_TRUE(m.geiger.free_running);
    EXPECT_EQ(m.geiger.dead_time_ns, 60000);
    EXPECT_NE(describe(m).find("free-running (dead time carried across pulses)"),
              std::string::npos);
    EXPECT_FALSE(preset("gmapd-32x32").geiger.free_running);
}

TEST(Array, geiger_detector_keys) {
    const auto m = load_sensor_yaml_text(
        "base: vlp16\ndetector: {type: geiger, pde: 0.3, bin_ns: 0.5, dark_count_rate_khz: 20, "
        "dead_time_ns: 40, paralyzable: true, jitter_ns: 0.1, afterpulse_probability: 0.02, "
        "afterpulse_delay_ns: 800, max_events: 4}\n",
        "g.yaml");
    EXPECT_EQ(m.detector, DetectorKind::Geiger);
    EXPECT_EQ(m.receiver.quantum_efficiency, 0.3);
    EXPECT_EQ(m.geiger.bin_ns, 0.5);
    EXPECT_EQ(m.geiger.dark_count_rate_hz, 2e4);
    EXPECT_EQ(m.geiger.dead_time_ns, 40);
    EXPECT_TRUE(m.geiger.paralyzable);
    EXPECT_EQ(m.geiger.jitter_ns, 0.1);
    EXPECT_EQ(m.geiger.afterpulse_probability, 0.02);
    EXPECT_EQ(m.geiger.afterpulse_delay_ns, 800);
    EXPECT_EQ(m.geiger.max_events, 4);
    EXPECT_NE(describe(m).find("detector: Geiger-mode, PDE 0.300"), std::string::npos);
}

// The ALIRT-like preset, and a file based on it: its keys apply to the laser (the flash's
// divergence), the array is made again over them; keys the array sets are refused.
TEST(Array, gmapd_preset_and_files_based_on_it) {
    const auto p = preset("gmapd-32x32");
    ASSERT_TRUE(p.array.on());
    EXPECT_EQ(p.array.pixels(), 1024u);
    EXPECT_EQ(p.detector, DetectorKind::Geiger);
    EXPECT_DOUBLE_EQ(p.scan->pulse_rate_hz(), 20e3 * 1024);
    EXPECT_DOUBLE_EQ(p.array.laser_divergence_rad, 2.5e-3);
    // Photon-starved: the centre pixel over a 10 % surface at the gate's end expects 0.3–1
    // photo-electron (its share of the pulse and its fill factor of the whole-beam link).
    BeamParams laser = p.beam;
    const double centre = double(p.array.share[16 * 32 + 16]) * p.array.fill_factor *
                          lambertian_electrons(laser, p.receiver, 0.1, 1400.0);
    std::printf("gmapd-32x32: centre pixel, 10 %% at 1400 m: %.3f photo-electrons\n", centre);
    EXPECT_GT(centre, 0.3);
    EXPECT_LT(centre, 1.0);
    const auto wide = load_sensor_yaml_text("base: gmapd-32x32\nbeam: {divergence_mrad: 4}\n", "w");
    EXPECT_DOUBLE_EQ(wide.array.laser_divergence_rad, 4e-3);
    EXPECT_DOUBLE_EQ(wide.beam.divergence_rad, p.beam.divergence_rad);       // the pixel's cone
    EXPECT_LT(wide.array.share[16 * 32 + 16], p.array.share[16 * 32 + 16]);  // spread wider
    EXPECT_EQ(dynamic_cast<const ArrayScan&>(*wide.scan).laser().kind(),
              dynamic_cast<const ArrayScan&>(*p.scan).laser().kind());
    const auto half = load_sensor_yaml_text("base: gmapd-32x32\narray: {columns: 16}\n", "h");
    EXPECT_EQ(half.array.pixels(), 16u * 32u);
    EXPECT_DOUBLE_EQ(half.scan->pulse_rate_hz(), 20e3 * 512);
    const auto same = load_sensor_yaml_text("base: gmapd-32x32\n", "s");
    EXPECT_EQ(same.array.share, p.array.share);
    EXPECT_DOUBLE_EQ(same.receiver.f_number, p.receiver.f_number);
    for (const std::string& bad : {std::string("base: gmapd-32x32\nreceiver: {f_number: 2}\n"),
                                   std::string("base: gmapd-32x32\nnoise: {range_sigma_m: 0.1}\n")})
        EXPECT_THROW(load_sensor_yaml_text(bad, "bad.yaml"), ConfigError) << bad;
}

// The frame presets (docs/photon-counting.md §3): a staring laser behind a flash array, a frame
// per pulse; the field from pitch and focal length; a physical lens (f-number ≥ 1); the expected
// photo-electrons of a pixel over a 10 % surface at the design range.
TEST(Array, frame_presets_stare_with_a_flash) {
    struct Case {
        const char* name;
        std::uint32_t columns, rows;
        double frame_hz, field_h_deg, field_v_deg, range_m;
        bool nadir;
    };
    for (const Case& c : {Case{"nvig-320x240", 320, 240, 10, 20.0, 15.07, 500, true},
                          Case{"flash-128x32", 128, 32, 25, 100.0, 33.2, 30, false}}) {
        SCOPED_TRACE(c.name);
        const auto p = preset(c.name);
        ASSERT_TRUE(p.array.on());
        EXPECT_EQ(p.array.columns, c.columns);
        EXPECT_EQ(p.array.rows, c.rows);
        const auto& laser = dynamic_cast<const ArrayScan&>(*p.scan).laser();
        ASSERT_EQ(laser.kind(), "staring");
        EXPECT_DOUBLE_EQ(laser.pulse_rate_hz(), c.frame_hz);
        EXPECT_EQ(p.airborne, c.nadir);
        PulseSpec first[2];
        laser.pulses(0, 2, first);
        EXPECT_EQ(first[1].t_ns, static_cast<std::int64_t>(1e9 / c.frame_hz));
        EXPECT_EQ(first[0].dir, c.nadir ? Eigen::Vector3f(0, 0, -1) : Eigen::Vector3f(1, 0, 0));
        const double ifov = p.array.pitch_m / p.array.focal_length_m;
        const auto field = [&](std::uint32_t n) {
            return 2 * std::atan(0.5 * n * ifov) * 180 / std::numbers::pi;
        };
        EXPECT_NEAR(field(c.columns), c.field_h_deg, 0.1);
        EXPECT_NEAR(field(c.rows), c.field_v_deg, 0.1);
        EXPECT_GE(p.receiver.f_number, 1.0);
        BeamParams laser_beam = p.beam;
        const double n = double(p.array.share[0]) * p.array.fill_factor *
                         lambertian_electrons(laser_beam, p.receiver, 0.1, c.range_m);
        std::printf("%s: a pixel, 10 %% at %.0f m: %.0f photo-electrons, f/%.2f\n", c.name,
                    c.range_m, n, p.receiver.f_number);
        EXPECT_GT(n, 100.0);
        EXPECT_LT(n, 1000.0);
        EXPECT_NE(describe(p).find("staring"), std::string::npos);
    }
    EXPECT_THROW(load_sensor_yaml_text("base: nvig-320x240\nairborne: {prf_khz: 10}\n", "x"),
                 ConfigError);
}

}  // namespace
}  // namespace mirage::sensor
