// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "cli_run.hpp"
#include "mirage/las/las_reader.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

TEST(Cli, render_writes_a_valid_las_with_a_summary) {
    TempDir tmp;
    const auto out = tmp.file("a.las");
    const auto r = run_mirage(
        "render --scene demo --sensor vlp16 --trajectory demo-car --duration 0.2 --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("pulses"), std::string::npos);
    EXPECT_NE(r.output.find("voids"), std::string::npos);
    const auto f = las::LasFile::read(out);
    EXPECT_TRUE(f.validate().empty());
    EXPECT_GT(f.header().point_count, 20'000u);
    EXPECT_EQ(f.header().point_format, 6);
    EXPECT_FALSE(f.header().wkt.empty());
    const auto info = run_mirage("las-info " + out);
    EXPECT_EQ(info.exit_code, 0) << info.output;
    EXPECT_NE(info.output.find("valid"), std::string::npos);
}

// `render --coincidence` (docs/photon-counting.md §5): a Geiger-mode render's events and its
// coincidence points as valid LAS; --pulses-per-cell caps the gates each cell counts.
TEST(Cli, render_coincidence_writes_points_and_a_dwell_caps_the_gates_per_cell) {
    TempDir tmp;
    const std::string scene =
        "render --scene demo --sensor gmapd-32x32 --trajectory static:0,0,1200 --duration 0.02 "
        "--sun-elevation-deg -1 --out " +
        tmp.file("e.las");
    const std::string base = scene + " --threads 2 --coincidence " + tmp.file("c.las");
    const auto gates = [](const std::string& out) {
        const auto at = out.find("coincidence: ");
        return at == std::string::npos ? 0.0 : std::stod(out.substr(at + 13));
    };
    const auto all = run_mirage(base);
    ASSERT_EQ(all.exit_code, 0) << all.output;
    EXPECT_EQ(gates(all.output), 409600.0) << all.output;  // 0.02 s × 20 kHz × 1024 pixels
    const auto points = las::LasFile::read(tmp.file("c.las"));
    EXPECT_TRUE(points.validate().empty());
    EXPECT_GT(points.points().size(), 500u);
    // One thread gives the same points in the same order (docs/photon-counting.md §5).
    const auto one = run_mirage(scene + " --threads 1 --coincidence " + tmp.file("c1.las"));
    ASSERT_EQ(one.exit_code, 0) << one.output;
    const auto single = las::LasFile::read(tmp.file("c1.las"));
    ASSERT_EQ(single.points().size(), points.points().size());
    for (std::size_t k = 0; k < single.points().size(); ++k) {
        ASSERT_EQ(single.points()[k].x, points.points()[k].x) << k;
        ASSERT_EQ(single.points()[k].z, points.points()[k].z) << k;
        ASSERT_EQ(single.points()[k].intensity, points.points()[k].intensity) << k;
    }
    const auto dwell = run_mirage(base + " --pulses-per-cell 20");
    ASSERT_EQ(dwell.exit_code, 0) << dwell.output;
    EXPECT_GT(gates(dwell.output), 1000.0) << dwell.output;
    EXPECT_LT(gates(dwell.output), 0.5 * gates(all.output)) << dwell.output;
    EXPECT_LT(las::LasFile::read(tmp.file("c.las")).points().size(), points.points().size());
}

// A frame preset (docs/photon-counting.md §3): one flash of nvig-320x240 from 500 m over the
// demo town lights its 20° × 15° field: a point per pixel over about 2·500·tan 7.5° by
// 2·500·tan 10° (rows along x, columns along y; the terrain's ±8 m moves the edges by ~2 %).
TEST(Cli, render_one_frame_of_the_nvig_preset_covers_its_field) {
    TempDir tmp;
    const auto r = run_mirage(
        "render --scene demo --sensor nvig-320x240 --trajectory static:100,100,500 --duration 0.1 "
        "--out " +
        tmp.file("f.las"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("76800 pulses"), std::string::npos) << r.output;
    const auto f = las::LasFile::read(tmp.file("f.las"));
    const auto& h = f.header();
    EXPECT_GT(h.point_count, 76000u);
    const double along = h.max[0] - h.min[0], across = h.max[1] - h.min[1];
    std::printf("one nvig frame from 500 m: %llu points over %.1f x %.1f m\n",
                static_cast<unsigned long long>(h.point_count), along, across);
    EXPECT_NEAR(along, 2 * 500 * std::tan(7.535 * std::numbers::pi / 180), 0.05 * along);
    EXPECT_NEAR(across, 2 * 500 * std::tan(10.0 * std::numbers::pi / 180), 0.05 * across);
}

// `render --waveform` (docs/commands.md): format 6 becomes 9, the packets land in the EVLR, or
// in the .wdp with --wdp, and las-info validates them and draws chosen pulses.
TEST(Cli, render_waveform_writes_packets_that_las_info_validates_and_draws) {
    TempDir tmp;
    const std::string sensor = (source_dir() / "recordings/sensors/als-waveform.yaml").string();
    const std::string base =
        "render --scene demo --trajectory demo-flight --duration 0.02 "
        "--waveform --waveform-samples 128 --sensor " +
        sensor;
    auto r = run_mirage(base + " --out " + tmp.file("in.las"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_mirage(base + " --wdp --out " + tmp.file("ex.las"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(std::filesystem::exists(tmp.file("in.wdp")));
    ASSERT_TRUE(std::filesystem::exists(tmp.file("ex.wdp")));
    const auto in = las::LasFile::read(tmp.file("in.las"));
    const auto ex = las::LasFile::read(tmp.file("ex.las"));
    EXPECT_TRUE(in.validate().empty()) << ::testing::PrintToString(in.validate());
    EXPECT_TRUE(ex.validate().empty()) << ::testing::PrintToString(ex.validate());
    EXPECT_EQ(in.header().point_format, 9);
    ASSERT_EQ(in.points().size(), ex.points().size());
    ASSERT_GT(in.points().size(), 5000u);
    for (std::size_t k = 0; k < in.points().size(); k += 97) {
        ASSERT_EQ(in.waveform(in.points()[k]).size(), 128u);
        ASSERT_EQ(in.waveform(in.points()[k]), ex.waveform(ex.points()[k])) << k;
    }
    r = run_mirage("las-info " + tmp.file("ex.las") + " --waveform-png " + tmp.file("w.png"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("waveforms in the .wdp file"), std::string::npos) << r.output;
    EXPECT_GT(std::filesystem::file_size(tmp.file("w.png")), 1000u);
    // A sensor without a digitiser cannot record; --wdp alone asks for nothing.
    r = run_mirage("render --scene demo --sensor vlp16 --waveform --out " + tmp.file("x.las"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    r = run_mirage("render --scene demo --sensor vlp16 --wdp --out " + tmp.file("x.las"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST(Cli, render_follows_a_csv_trajectory_with_either_interpolation) {
    TempDir tmp;
    const auto csv = tmp.file("t.csv");
    std::ofstream(csv) << "# a 2 s drive east, 1.8 m above the town's origin\n"
                          "time,x,y,z,roll,pitch,yaw\n"
                          "1388534418.0,-10,0,10,0,0,0\n"
                          "1388534419.0,0,0,10,0,0,10\n"
                          "1388534420.0,10,0,10,0,0,20\n";
    for (const char* interp : {"linear", "cubic"}) {
        const auto out = tmp.file(std::string(interp) + ".las");
        const auto r = run_mirage("render --scene demo --sensor vlp16 --trajectory " + csv +
                                  " --interpolation " + interp + " --out " + out);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const auto f = las::LasFile::read(out);
        EXPECT_TRUE(f.validate().empty());
        // 2 s of a VLP-16 (289 352 pulses/s), most of which see the town.
        EXPECT_GT(f.header().point_count, 200'000u) << interp;
        EXPECT_LT(f.header().point_count, 2 * 289'356u) << interp;
    }
}

TEST(Cli, bad_inputs_fail_with_a_clear_message_and_the_documented_exit_code) {
    TempDir tmp;
    const auto out = tmp.file("b.las");
    auto r = run_mirage("render --scene no_such_scene.yaml --sensor vlp16 --out " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("no_such_scene.yaml"), std::string::npos) << r.output;
    r = run_mirage("render --scene demo --sensor no-such-sensor --out " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("no-such-sensor"), std::string::npos) << r.output;
    r = run_mirage("render --scene demo --sensor vlp16 --duration abc --out " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--duration"), std::string::npos) << r.output;
    r = run_mirage("render --scene demo --sensor vlp16 --format 5 --out " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    r = run_mirage("render --scene demo --sensor vlp16 --duration 0.01 --out /dev/null/x.las");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("/dev/null/x.las"), std::string::npos) << r.output;
    // las-info on a file that is not LAS.
    const auto junk = tmp.file("junk.las");
    std::ofstream(junk) << "not a las file at all";
    r = run_mirage("las-info " + junk);
    EXPECT_EQ(r.exit_code, 1) << r.output;
}

}  // namespace
}  // namespace mirage::test
