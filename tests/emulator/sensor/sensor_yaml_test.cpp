// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/airborne.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/sensor/spinning.hpp"
#include "test_paths.hpp"

namespace mirage::sensor {
namespace {

std::string write(const test::TempDir& dir, const std::string& name, const std::string& text) {
    const std::string path = dir.file(name);
    std::ofstream(path) << text;
    return path;
}

// The ConfigError message of loading `text`, or "" when it loads.
std::string error_of(const std::string& text) {
    test::TempDir dir;
    const std::string path = write(dir, "x.yaml", text);
    try {
        load_sensor_yaml(path);
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        const std::string prefix = "sensor '" + path + "': ";
        EXPECT_EQ(what.rfind(prefix, 0), 0u) << what;
        return what.substr(std::min(what.size(), prefix.size()));
    }
    return "";
}

std::size_t count(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1))
        ++n;
    return n;
}

// The in-memory entry point (fuzz_sensor_yaml) reads like the file and takes its default name
// from the name it is given.
TEST(SensorYaml, text_in_memory_reads_like_the_file) {
    const SensorModel m = load_sensor_yaml_text("base: vlp16\npoint_source_id: 9\n", "mem.yaml");
    EXPECT_EQ(m.name, "mem");
    EXPECT_EQ(m.point_source_id, 9);
    ASSERT_TRUE(m.scan);
    EXPECT_EQ(m.scan->channels(), 16u);
    try {
        load_sensor_yaml_text("base: nope\n", "mem.yaml");
        ADD_FAILURE() << "unknown base accepted";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("sensor 'mem.yaml': base: unknown preset 'nope'", 0),
                  0u)
            << e.what();
    }
}

TEST(SensorYaml, overrides_reach_every_channel) {
    test::TempDir dir;
    const auto path = write(dir, "v.yaml", R"(base: vlp16
beam:
  pulse_energy_uj: 0.25
  divergence_mrad: 1.5
  profile: tophat
  sub_rays: 19
receiver:
  max_range_m: 150
  min_range_m: 0.8
noise:
  range_sigma_m: 0.01
  jitter_sigma_mrad: 0.2
point_source_id: 7
)");
    const SensorModel m = load_sensor_yaml(path);
    EXPECT_EQ(m.name, "v");
    EXPECT_EQ(m.scan->channels(), 16u);
    EXPECT_DOUBLE_EQ(m.beam.pulse_energy_j, 0.25e-6);
    EXPECT_DOUBLE_EQ(m.beam.divergence_rad, 1.5e-3);
    EXPECT_EQ(m.beam.profile, BeamProfile::TopHat);
    EXPECT_EQ(m.beam.sub_rays, 19);
    EXPECT_DOUBLE_EQ(m.receiver.max_range_m, 150.0);
    EXPECT_DOUBLE_EQ(m.receiver.min_range_m, 0.8);
    EXPECT_DOUBLE_EQ(m.noise.range_sigma_m, 0.01);
    EXPECT_DOUBLE_EQ(m.noise.jitter_sigma_rad, 0.2e-3);
    EXPECT_EQ(m.point_source_id, 7);
    EXPECT_DOUBLE_EQ(m.beam.wavelength_m, 905e-9);  // untouched base value
    // Each of the 16 channel rows of the start-up print carries the overridden values.
    const std::string d = describe(m);
    EXPECT_EQ(count(d, "0.250 uJ 1.500 mrad sub-rays 19 range 0.80-150.0 m"), 16u) << d;
    for (int c = 0; c < 16; ++c)
        EXPECT_NE(d.find("ch " + std::string(c < 10 ? "  " : " ") + std::to_string(c) + ":"),
                  std::string::npos);
}

TEST(SensorYaml, rpm_override_changes_the_azimuth_step) {
    test::TempDir dir;
    const auto m = load_sensor_yaml(write(dir, "r.yaml", "base: vlp16\nspinning: {rpm: 1200}\n"));
    const auto* s = dynamic_cast<const SpinningPattern*>(m.scan.get());
    ASSERT_NE(s, nullptr);
    EXPECT_NEAR(s->azimuth_step_deg(), 360.0 * 20 * 55.296e-6, 1e-12);
    EXPECT_NEAR(m.scan->pulse_rate_hz(), 16 / 55.296e-6, 1e-6);  // firing rate unchanged
    EXPECT_EQ(error_of("base: vlp16\nspinning: {rpm: 1500}\n"),
              "spinning.rpm: 1500 is outside [300, 1200]");
    EXPECT_EQ(error_of("base: hdl64e-s3\nspinning: {rpm: 250}\n"),
              "spinning.rpm: 250 is outside [300, 1200]");
    EXPECT_NE(
        error_of("base: os1-64-1024x10\nspinning: {rpm: 1200}\n").find("spinning.rpm: Ouster"),
        std::string::npos);
}

TEST(SensorYaml, custom_spinning_sensor_without_base) {
    test::TempDir dir;
    const auto m = load_sensor_yaml(write(dir, "c.yaml", R"(name: four
spinning:
  rpm: 600
  sequence_period_us: 20
  lasers:
    - {elevation_deg: -10, firing_offset_us: 15}
    - {elevation_deg: 10, azimuth_offset_deg: 1.5, firing_offset_us: 5}
    - {elevation_deg: 0}
)"));
    EXPECT_EQ(m.name, "four");
    EXPECT_FALSE(m.airborne);
    EXPECT_EQ(m.scan->channels(), 3u);
    EXPECT_DOUBLE_EQ(m.scan->pulse_rate_hz(), 150'000.0);
    std::vector<PulseSpec> p(4);
    m.scan->pulses(0, 4, p.data());
    EXPECT_EQ(p[0].channel, 2);
    EXPECT_EQ(p[1].channel, 1);
    EXPECT_EQ(p[1].t_ns, 5000);
    EXPECT_NEAR(p[1].azimuth_deg, 1.5 + 3600.0 * 5e-6, 1e-5);
    EXPECT_EQ(p[2].channel, 0);
    EXPECT_EQ(p[3].t_ns, 20'000);
}

TEST(SensorYaml, airborne_overrides_and_custom_patterns) {
    test::TempDir dir;
    const auto m = load_sensor_yaml(write(dir, "a.yaml", R"(base: als-mirror
airborne: {pattern: palmer, prf_khz: 200, scan_rate_hz: 20, fov_deg: 30, tilt_deg: 5}
)"));
    EXPECT_TRUE(m.airborne);
    const auto* a = dynamic_cast<const AirbornePattern*>(m.scan.get());
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->config().kind, AirborneKind::Palmer);
    EXPECT_DOUBLE_EQ(a->config().prf_hz, 200e3);
    EXPECT_DOUBLE_EQ(a->config().tilt_deg, 5.0);
    EXPECT_EQ(m.scan->kind(), "palmer");

    const auto p = load_sensor_yaml(write(dir, "p.yaml", R"(airborne:
  pattern: polygon
  prf_khz: 400
  scan_rate_hz: 25
  facets: 4
  fov_deg: 50
)"));
    EXPECT_EQ(p.scan->kind(), "polygon");
    EXPECT_DOUBLE_EQ(dynamic_cast<const AirbornePattern&>(*p.scan).config().lines_per_s(), 100.0);
}

TEST(SensorYaml, errors_name_the_key_path) {
    EXPECT_EQ(error_of("base: vlp16\nbeam: {sub_rays: 5}\n"),
              "beam.sub_rays: 5 is not a hexagonal count (1, 7, 19, 37, …)");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {sub_rays: 7.5}\n"),
              "beam.sub_rays: expected an integer, got '7.5'");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {divergence_mrad: abc}\n"),
              "beam.divergence_mrad: expected a number, got 'abc'");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {profile: flat}\n"),
              "beam.profile: 'flat' is not gaussian or tophat");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {eta_receiver: 1.5}\n"),
              "receiver.eta_receiver: 1.5 is outside (0, 1]");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {max_returns: 0}\n"),
              "receiver.max_returns: 0 is outside [1, 8]");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {max_returns: 9}\n"),
              "receiver.max_returns: 9 is outside [1, 8]");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {min_range_m: 200}\n"),
              "receiver.min_range_m: min_range_m 200 must be below max_range_m 100");
    EXPECT_EQ(error_of("base: vlp16\nnoise: {range_sigma_m: -1}\n"),
              "noise.range_sigma_m: -1 is outside [0, 100]");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {wavelenght_nm: 905}\n")
                  .rfind("beam.wavelenght_nm: unknown key (expected one of wavelength_nm, ", 0),
              0u);
    EXPECT_EQ(error_of("base: vlp16\nbeams: {}\n").rfind("beams: unknown key", 0), 0u);
    EXPECT_EQ(error_of("base: vlp17\n").rfind("base: unknown preset 'vlp17' (known: vlp16, ", 0),
              0u);
    EXPECT_EQ(error_of("base: vlp16\nairborne: {fov_deg: 30}\n"),
              "airborne: base 'vlp16' is a spinning sensor");
    EXPECT_EQ(error_of("base: als-mirror\nspinning: {rpm: 600}\n"),
              "spinning: base 'als-mirror' is an airborne sensor");
    EXPECT_EQ(error_of("base: als-mirror\nairborne: {facets: 4}\n"),
              "airborne.facets: only for pattern polygon (pattern is sawtooth)");
    EXPECT_EQ(error_of("base: als-mirror\nairborne: {fov_deg: 180}\n"),
              "airborne.fov_deg: 180 is outside (0, 180)");
    EXPECT_EQ(error_of("base: als-mirror\nairborne: {pattern: zigzag}\n"),
              "airborne.pattern: 'zigzag' is not sawtooth, sine, polygon or palmer");
    EXPECT_EQ(error_of("airborne: {pattern: sine, prf_khz: 100, fov_deg: 30}\n"),
              "airborne.scan_rate_hz: required when there is no base preset");
    EXPECT_EQ(error_of("spinning: {sequence_period_us: 10, lasers: [{elevation_deg: 0}, "
                       "{azimuth_offset_deg: 1}]}\n"),
              "spinning.lasers[1].elevation_deg: required");
    EXPECT_EQ(error_of("spinning: {sequence_period_us: 10, lasers: [{elevation_deg: 0, "
                       "firing_offset_us: 12}]}\n"),
              "spinning.lasers[0].firing_offset_us: 12 is not below the sequence period 10 µs");
    EXPECT_EQ(error_of("spinning: {sequence_period_us: 10, lasers: [{elevation_deg: 91}]}\n"),
              "spinning.lasers[0].elevation_deg: 91 is outside [-90, 90]");
    EXPECT_EQ(error_of("spinning: {lasers: [{elevation_deg: 1}]}\n"),
              "spinning.sequence_period_us: required when there is no base preset");
    EXPECT_EQ(error_of("base: vlp16\npoint_source_id: 70000\n"),
              "point_source_id: 70000 is outside [0, 65535]");
    EXPECT_EQ(error_of("name: nothing\n"),
              "needs 'base: <preset>' or a 'spinning' or 'airborne' section");
    EXPECT_EQ(error_of("- a\n- b\n"), "expected a mapping with 'base' and/or sensor sections");
    EXPECT_EQ(error_of("base: vlp16\nbeam: [1, 2]\n"), "beam: expected a mapping of keys");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {sub_rays: 7}\n"), "");
}

// `detector:` selects the linear-mode digitiser and sets it; its settings are refused with the
// discrete detector (they would do nothing) and out of range, each naming the key.
TEST(SensorYaml, detector_section_selects_and_sets_the_linear_detector) {
    test::TempDir dir;
    const SensorModel m = load_sensor_yaml(write(dir, "w.yaml", R"(base: vlp16
beam: {footprint_radius: 2}
detector: {type: linear, sample_rate_gsps: 2, bits: 14, offset_counts: 200, apd_gain: 80,
           apd_k: 0.3, thermal_noise_pe: 1.5, dark_current_na: 3, threshold_counts: 40,
           gain_counts_per_pe: 2.5}
)"));
    EXPECT_EQ(m.detector, DetectorKind::Linear);
    EXPECT_EQ(m.linear.sample_rate_gsps, 2.0);
    EXPECT_EQ(m.linear.bits, 14);
    EXPECT_EQ(m.linear.offset_counts, 200.0);
    EXPECT_EQ(m.linear.apd_gain, 80.0);
    EXPECT_EQ(m.linear.apd_k, 0.3);
    EXPECT_EQ(m.linear.thermal_noise_pe, 1.5);
    EXPECT_EQ(m.linear.dark_current_na, 3.0);
    EXPECT_EQ(m.linear.threshold_counts, 40.0);
    EXPECT_EQ(m.linear.gain_counts_per_pe, 2.5);
    EXPECT_EQ(m.beam.footprint_radius, 2.0);
    EXPECT_EQ(preset("vlp16").detector, DetectorKind::Discrete);

    EXPECT_EQ(error_of("base: vlp16\ndetector: {bits: 12}\n"),
              "detector.bits: only with detector.type: linear");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: photon}\n"),
              "detector.type: 'photon' is not discrete, linear or geiger");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, bits: 33}\n"),
              "detector.bits: 33 is outside [1, 32]");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, apd_k: 1.5}\n"),
              "detector.apd_k: 1.5 is outside [0, 1]");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, bits: 8, offset_counts: 300}\n"),
              "detector.offset_counts: 300 is not below full scale 255 of 8 bits");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {profile: tophat, footprint_radius: 2}\n"),
              "beam.footprint_radius: a top-hat beam has no light beyond its radius (use 1)");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {threshold_gamma: 2}\ndetector: {type: linear}\n"),
              "receiver.threshold_gamma: the discrete detector's void rule: the linear detector "
              "has detector.threshold_counts and detector.thermal_noise_pe, the Geiger one its "
              "photon statistics");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {threshold_gamma: 2}\ndetector: {type: geiger}\n"),
              "receiver.threshold_gamma: the discrete detector's void rule: the linear detector "
              "has detector.threshold_counts and detector.thermal_noise_pe, the Geiger one its "
              "photon statistics");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {min_range_m: 1, max_range_m: 1.5}\n"),
              "receiver.max_range_m: the range gate (3.33564 ns two-way) is shorter than the pulse "
              "(5 ns)");
    EXPECT_EQ(error_of("base: vlp16\nbeam: {footprint_radius: 4}\n"),
              "beam.footprint_radius: 4 is outside (0, 3]");
}

// `detector.timing` chooses how echoes are timed; `cfd_fraction` belongs to the constant-fraction
// timing alone (it would do nothing with the others).
TEST(SensorYaml, detector_timing_and_cfd_fraction) {
    test::TempDir dir;
    const auto timing_of = [&](const std::string& text) {
        return load_sensor_yaml(write(dir, "t.yaml", "base: vlp16\n" + text)).linear;
    };
    EXPECT_EQ(timing_of("detector: {type: linear}\n").timing, EchoTiming::Peak);
    const auto cfd =
        timing_of("detector: {type: linear, timing: constant_fraction, cfd_fraction: 0.3}\n");
    EXPECT_EQ(cfd.timing, EchoTiming::ConstantFraction);
    EXPECT_EQ(cfd.cfd_fraction, 0.3);
    EXPECT_EQ(timing_of("detector: {type: linear, timing: decomposition}\n").timing,
              EchoTiming::Decomposition);
    EXPECT_EQ(error_of("base: vlp16\ndetector: {timing: peak}\n"),
              "detector.timing: only with detector.type: linear");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, timing: leading}\n"),
              "detector.timing: 'leading' is not peak, constant_fraction or decomposition");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, cfd_fraction: 0.5}\n"),
              "detector.cfd_fraction: only with detector.timing: constant_fraction");
    EXPECT_EQ(error_of("base: vlp16\ndetector: {type: linear, timing: constant_fraction, "
                       "cfd_fraction: 1}\n"),
              "detector.cfd_fraction: 1 is outside [0.01, 0.99]");
}

// `receiver.speckle_cells`: a number of cells ≥ 1, 0 for none, or `auto`, which takes M from the
// aperture and the spot: 1 + (π·D·θ_b/(2λ))² (VLP-16: 25 mm, 1.5 mrad, 905 nm -> 4237.5).
TEST(SensorYaml, speckle_cells_is_a_number_zero_or_auto) {
    test::TempDir dir;
    const auto load = [&](const std::string& text) {
        return load_sensor_yaml(write(dir, "s.yaml", "base: vlp16\n" + text));
    };
    EXPECT_EQ(speckle_cells(preset("vlp16")), 0.0);
    EXPECT_EQ(speckle_cells(load("receiver: {speckle_cells: 4}\n")), 4.0);
    EXPECT_EQ(speckle_cells(load("receiver: {speckle_cells: 0}\n")), 0.0);
    const double x = std::numbers::pi * 0.025 * 1.5e-3 / (2 * 905e-9);
    EXPECT_NEAR(speckle_cells(load("receiver: {speckle_cells: auto}\n")), 1 + x * x, 1e-9);
    EXPECT_NEAR(1 + x * x, 4237.5, 0.1);
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {speckle_cells: 0.5}\n"),
              "receiver.speckle_cells: 0.5 is outside [1, 1e+09]");
    EXPECT_EQ(error_of("base: vlp16\nreceiver: {speckle_cells: many}\n"),
              "receiver.speckle_cells: expected a number, got 'many'");
}

TEST(SensorYaml, resolve_takes_a_preset_name_or_a_file) {
    EXPECT_EQ(resolve_sensor("hdl32e").name, "hdl32e");
    test::TempDir dir;
    const auto path = write(dir, "mine.yaml", "base: vlp32c\nspinning: {rpm: 300}\n");
    EXPECT_EQ(resolve_sensor(path).name, "mine");
    try {
        resolve_sensor("vlp-16");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("sensor 'vlp-16': neither a preset (vlp16, vlp16-hires", 0), 0u)
            << what;
        EXPECT_NE(what.find("als-palmer"), std::string::npos) << what;
    }
    EXPECT_THROW(load_sensor_yaml(dir.file("missing.yaml")), IoError);
}

TEST(SensorYaml, example_files_in_recordings_load) {
    const auto folder = test::source_dir() / "recordings" / "sensors";
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.path().extension() != ".yaml") continue;
        ++files;
        SensorModel m;
        ASSERT_NO_THROW(m = load_sensor_yaml(entry.path().string())) << entry.path();
        EXPECT_TRUE(m.scan) << entry.path();
        EXPECT_GT(m.scan->pulse_rate_hz(), 0.0);
    }
    EXPECT_GE(files, 4);
    const auto v = load_sensor_yaml((folder / "vlp16-footprint.yaml").string());
    EXPECT_EQ(v.beam.sub_rays, 7);
    EXPECT_EQ(v.point_source_id, 2);
    EXPECT_NEAR(dynamic_cast<const SpinningPattern&>(*v.scan).rpm(), 900.0, 1e-9);
}

}  // namespace
}  // namespace mirage::sensor

namespace mirage::sensor {
namespace {

// The wire family is a property of the model: a renamed sensor file keeps its base's packets,
// another laser table has none, and presets say theirs.
TEST(SensorWire, family_comes_from_the_model_not_the_name) {
    EXPECT_EQ(preset("vlp16").wire.family, WireFamily::Velodyne);
    EXPECT_EQ(preset("hdl64e-s3").wire.model, "hdl64e-s3");
    EXPECT_EQ(preset("os1-64-1024x10").wire.family, WireFamily::Ouster);
    EXPECT_EQ(preset("als-mirror").wire.family, WireFamily::None);

    test::TempDir dir;
    const auto renamed =
        load_sensor_yaml(write(dir, "front.yaml", "base: os1-64-1024x10\nname: front\n"));
    EXPECT_EQ(renamed.name, "front");
    EXPECT_EQ(renamed.wire.family, WireFamily::Ouster);
    EXPECT_EQ(renamed.wire.model, "os1-64-1024x10");

    const auto fewer = load_sensor_yaml(write(dir, "two.yaml", R"(base: vlp16
spinning:
  lasers:
    - {elevation_deg: -1, azimuth_offset_deg: 0, firing_offset_us: 0}
    - {elevation_deg: 1, azimuth_offset_deg: 0, firing_offset_us: 2.304}
)"));
    EXPECT_EQ(fewer.wire.family, WireFamily::None);
}

}  // namespace
}  // namespace mirage::sensor
