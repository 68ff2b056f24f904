// SPDX-License-Identifier: Apache-2.0
// Measured pulse shapes from text: the accepted syntax, errors naming the line, and the sensor
// YAML key that reads them.
#include "mirage/sensor/pulse_table.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "mirage/core/error.hpp"
#include "mirage/sensor/pulse_shape.hpp"
#include "mirage/sensor/sensor.hpp"
#include "test_paths.hpp"

namespace mirage::sensor {
namespace {

std::string error_of(std::string_view text) {
    try {
        parse_pulse_table(text, "p.txt");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "no error";
}

TEST(PulseTable, commas_blanks_comments_and_crlf_are_read) {
    const auto t = parse_pulse_table("# t_ns, power\r\n0, 0\r\n\n 1\t5  # peak\n3,0\n", "p.txt");
    EXPECT_EQ(t.t_ns, (std::vector<double>{0, 1, 3}));
    EXPECT_EQ(t.power, (std::vector<double>{0, 5, 0}));
    const auto s = PulseShape::tabulated(t.t_ns, t.power, "p.txt");
    EXPECT_NEAR(s.fwhm_ns(), 1.5, 1e-12);
}

// A last sample astronomically far from the rest (fuzz_pulse_table's find): the half-maximum
// crossings are taken from the samples above half, so the width is the near one, 1.75 ns
// (0.25 on the rise to 2 at the sample holding exactly half), not a negative rounding artefact.
TEST(PulseTable, a_far_last_sample_leaves_the_width_exact) {
    const auto s = PulseShape::tabulated({0, 0.5, 1, 2, 1.1e84}, {0, 2, 1, 1, 0.6}, "p.txt");
    EXPECT_DOUBLE_EQ(s.fwhm_ns(), 1.75);
}

TEST(PulseTable, bad_text_is_a_config_error_naming_the_line) {
    EXPECT_EQ(error_of("0 0\n1 x\n"),
              "pulse shape 'p.txt': line 2: expected two finite numbers: time_ns, relative_power");
    EXPECT_EQ(error_of("0 0 0\n"), "pulse shape 'p.txt': line 1: more than two values");
    EXPECT_EQ(error_of("0 0\n1 inf\n"),
              "pulse shape 'p.txt': line 2: expected two finite numbers: time_ns, relative_power");
    EXPECT_EQ(error_of("0 1\n"),
              "pulse shape 'p.txt': needs at least 2 samples, one power per time");
    EXPECT_EQ(error_of("0 1\n2 1\n1 1\n"),
              "pulse shape 'p.txt': sample 2: times must increase strictly");
    EXPECT_EQ(error_of("0 -1\n1 1\n"),
              "pulse shape 'p.txt': sample 0: power must be finite and >= 0");
    EXPECT_EQ(error_of("0 0\n1 0\n"), "pulse shape 'p.txt': the shape has no area");
    EXPECT_EQ(error_of("0 0\n1e300 1e300\n"),
              "pulse shape 'p.txt': the shape's moments overflow a double");
    EXPECT_EQ(error_of(std::string(kMaxPulseTableBytes + 1, ' ')),
              "pulse shape 'p.txt': larger than 1048576 bytes");
}

// `beam.pulse_shape: <file>` is read relative to the sensor file; its FWHM is the pulse width,
// which may then not be given as well; a missing file names the key.
TEST(PulseTable, sensor_yaml_reads_the_shape_relative_to_its_file) {
    test::TempDir dir;
    std::ofstream(dir.file("tri.txt")) << "0 0\n1 5\n3 0\n";
    std::ofstream(dir.file("s.yaml")) << "base: vlp16\nbeam: {pulse_shape: tri.txt}\n";
    const SensorModel m = load_sensor_yaml(dir.file("s.yaml"));
    EXPECT_EQ(m.beam.pulse_t_ns.size(), 3U);
    EXPECT_NEAR(m.beam.pulse_width_s, 1.5e-9, 1e-21);
    std::ofstream(dir.file("both.yaml"))
        << "base: vlp16\nbeam: {pulse_shape: tri.txt, pulse_width_ns: 4}\n";
    EXPECT_THROW(load_sensor_yaml(dir.file("both.yaml")), ConfigError);
    std::ofstream(dir.file("missing.yaml")) << "base: vlp16\nbeam: {pulse_shape: none.txt}\n";
    try {
        load_sensor_yaml(dir.file("missing.yaml"));
        ADD_FAILURE() << "a missing shape file was accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("beam.pulse_shape: pulse shape '"), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(load_sensor_yaml_text("base: vlp16\nbeam: {pulse_shape: gaussian}\n", "g")
                    .beam.pulse_t_ns.empty());
}

}  // namespace
}  // namespace mirage::sensor
