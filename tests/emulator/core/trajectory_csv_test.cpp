// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <fstream>
#include <numbers>
#include <random>

#include "mirage/core/error.hpp"
#include "mirage/core/trajectory.hpp"
#include "test_paths.hpp"
#include "test_units.hpp"

using namespace mirage::core;
using mirage::test::TempDir;

namespace {

using mirage::test::kDeg;

std::string write(const TempDir& dir, const std::string& text, const std::string& name = "t.csv") {
    const std::string path = dir.file(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// Loads and returns the ConfigError message ("" if it loaded).
std::string load_error(const std::string& text, const Georef& g = {}) {
    TempDir dir;
    const std::string path = write(dir, text);
    try {
        load_trajectory_csv(path, g);
    } catch (const mirage::ConfigError& e) {
        return e.what();
    }
    return "";
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

}  // namespace

TEST(TrajectoryCsv, reads_time_xyz_rpy_with_comments_crlf_and_padding) {
    TempDir dir;
    const std::string path = write(dir,
                                   "# flight line 1\r\n"
                                   "\r\n"
                                   "time, x, y, z, roll, pitch, yaw\r\n"
                                   "1388534418.000000123, 1, 2, 3, 0, 0, 90\r\n"
                                   "# a comment between rows\n"
                                   "  1388534419.5 ,4,5,6,10,-5,-179\n");
    const Trajectory tr = load_trajectory_csv(path, Georef{});
    ASSERT_EQ(tr.samples().size(), 2u);
    EXPECT_EQ(tr.begin().time_since_epoch().count(), 1'388'534'418'000'000'123);
    EXPECT_EQ(tr.end().time_since_epoch().count(), 1'388'534'419'500'000'000);
    EXPECT_EQ(tr.samples()[0].pose.position, Eigen::Vector3d(1, 2, 3));
    const Eigen::Vector3d rpy = rpy_from_quaternion(tr.samples()[1].pose.attitude);
    EXPECT_NEAR(rpy.x(), 10 * kDeg, 1e-12);
    EXPECT_NEAR(rpy.y(), -5 * kDeg, 1e-12);
    EXPECT_NEAR(rpy.z(), -179 * kDeg, 1e-12);
    EXPECT_EQ(tr.interpolation(), Interpolation::Linear);
}

TEST(TrajectoryCsv, reads_utc_projected_positions_and_quaternions) {
    TempDir dir;
    const std::string path = write(dir,
                                   "utc,e,n,u,qw,qx,qy,qz\n"
                                   "2024-01-01T00:00:00Z,500010,5000020,130,1,0,0,0\n"
                                   "2024-01-01T00:00:00.25Z,500011,5000021,131,0,0,0,2\n");
    const Georef g = Georef::projected(32632, {500000, 5000000, 100});
    const Trajectory tr = load_trajectory_csv(path, g, Interpolation::Cubic);
    ASSERT_EQ(tr.samples().size(), 2u);
    EXPECT_EQ(tr.begin(), parse_time("2024-01-01T00:00:00Z"));
    EXPECT_EQ((tr.end() - tr.begin()).count(), 250'000'000);
    EXPECT_EQ(tr.samples()[0].pose.position, Eigen::Vector3d(10, 20, 30));
    EXPECT_EQ(tr.samples()[1].pose.position, Eigen::Vector3d(11, 21, 31));
    // (0,0,0,2) normalised: 180° about z.
    EXPECT_NEAR(std::abs(rpy_from_quaternion(tr.samples()[1].pose.attitude).z()), std::numbers::pi,
                1e-12);
    EXPECT_EQ(tr.interpolation(), Interpolation::Cubic);
}

TEST(TrajectoryCsv, reads_geodetic_positions_through_the_georef) {
    TempDir dir;
    const std::string path = write(dir,
                                   "time,lat,lon,h,roll,pitch,yaw\n"
                                   "100,45,9,100,0,0,0\n"
                                   "101,45.001,9,110,0,0,0\n");
    const Georef g = Georef::geodetic(45, 9, 100);
    const Trajectory tr = load_trajectory_csv(path, g);
    EXPECT_LT(tr.samples()[0].pose.position.norm(), 1e-3);
    const Eigen::Vector3d p1 = tr.samples()[1].pose.position;
    // 0.001° of latitude at 45° is 111.13 m of meridian; ×0.9996 on the central meridian.
    EXPECT_NEAR(p1.x(), 0.0, 1e-3);
    EXPECT_NEAR(p1.y(), 111.132 * 0.9996, 0.01);
    EXPECT_NEAR(p1.z(), 10.0, 1e-6);
}

TEST(TrajectoryCsv, bad_number_names_line_and_column) {
    const std::string e =
        load_error("time,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n2,0,abc,0,1,0,0,0\n");
    EXPECT_TRUE(contains(e, "line 3, column 'y'")) << e;
    EXPECT_TRUE(contains(e, "'abc' is not a number")) << e;
    EXPECT_EQ(e.rfind("trajectory '", 0), 0u) << e;
}

TEST(TrajectoryCsv, nan_and_inf_are_rejected) {
    const std::string nan = load_error("time,x,y,z,qw,qx,qy,qz\n1,0,0,nan,1,0,0,0\n");
    EXPECT_TRUE(contains(nan, "line 2, column 'z'")) << nan;
    EXPECT_TRUE(contains(nan, "not finite")) << nan;
    const std::string inf = load_error("time,x,y,z,roll,pitch,yaw\n\n1,0,0,0,0,-inf,0\n");
    EXPECT_TRUE(contains(inf, "line 3, column 'pitch'")) << inf;
    const std::string huge = load_error("time,x,y,z,roll,pitch,yaw\n1,1e999,0,0,0,0,0\n");
    EXPECT_TRUE(contains(huge, "line 2, column 'x'")) << huge;
}

TEST(TrajectoryCsv, missing_columns_are_named) {
    const std::string no_z = load_error("# c\ntime,x,y,qw,qx,qy,qz\n1,0,0,1,0,0,0\n");
    EXPECT_TRUE(contains(no_z, "line 2, column 'z': missing")) << no_z;
    const std::string no_time = load_error("x,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0\n");
    EXPECT_TRUE(contains(no_time, "line 1, column 'time': missing")) << no_time;
    const std::string no_att = load_error("time,x,y,z\n1,0,0,0\n");
    EXPECT_TRUE(contains(no_att, "line 1, column 'roll': missing")) << no_att;
}

TEST(TrajectoryCsv, unknown_duplicate_and_mixed_columns_are_rejected) {
    const std::string unknown = load_error("time,x,y,z,speed,qw,qx,qy,qz\n");
    EXPECT_TRUE(contains(unknown, "line 1, column 'speed': unknown column")) << unknown;
    const std::string dup = load_error("time,x,y,z,x,qw,qx,qy,qz\n");
    EXPECT_TRUE(contains(dup, "line 1, column 'x': duplicate")) << dup;
    const std::string mixed = load_error("time,x,y,z,e,qw,qx,qy,qz\n");
    EXPECT_TRUE(contains(mixed, "line 1, column 'e': conflicts")) << mixed;
    const std::string both = load_error("time,utc,x,y,z,qw,qx,qy,qz\n");
    EXPECT_TRUE(contains(both, "line 1, column 'utc': conflicts")) << both;
    const std::string no_crs = load_error("time,lat,lon,h,qw,qx,qy,qz\n1,45,9,0,1,0,0,0\n");
    EXPECT_TRUE(contains(no_crs, "line 1, column 'lat'")) << no_crs;
}

TEST(TrajectoryCsv, non_increasing_time_names_both_lines) {
    const std::string e =
        load_error("time,x,y,z,qw,qx,qy,qz\n1.5,0,0,0,1,0,0,0\n# gap\n1.500000000,0,0,0,1,0,0,0\n");
    EXPECT_TRUE(contains(e, "line 4, column 'time'")) << e;
    EXPECT_TRUE(contains(e, "line 2")) << e;
    const std::string back = load_error(
        "utc,x,y,z,qw,qx,qy,qz\n2024-01-01T00:00:01Z,0,0,0,1,0,0,0\n2024-01-01T00:00:00Z,0,0,0,1,0,"
        "0,0\n");
    EXPECT_TRUE(contains(back, "line 3, column 'utc'")) << back;
}

TEST(TrajectoryCsv, bad_times_and_field_counts_are_rejected) {
    const std::string sub_ns = load_error("time,x,y,z,qw,qx,qy,qz\n1.0000000001,0,0,0,1,0,0,0\n");
    EXPECT_TRUE(contains(sub_ns, "line 2, column 'time'")) << sub_ns;
    const std::string utc =
        load_error("utc,x,y,z,qw,qx,qy,qz\n2024-02-30T00:00:00Z,0,0,0,1,0,0,0\n");
    EXPECT_TRUE(contains(utc, "line 2, column 'utc'")) << utc;
    const std::string count = load_error("time,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0\n");
    EXPECT_TRUE(contains(count, "line 2: expected 8 fields")) << count;
    const std::string zero_q = load_error("time,x,y,z,qw,qx,qy,qz\n1,0,0,0,0,0,0,0\n");
    EXPECT_TRUE(contains(zero_q, "line 2, column 'qw': quaternion has zero norm")) << zero_q;
    const std::string lat =
        load_error("time,lat,lon,h,qw,qx,qy,qz\n1,95,9,0,1,0,0,0\n", Georef::geodetic(45, 9, 0));
    EXPECT_TRUE(contains(lat, "line 2, column 'lat'")) << lat;
}

TEST(TrajectoryCsv, needs_a_header_and_a_row) {
    const std::string empty = load_error("# only a comment\n\n");
    EXPECT_TRUE(contains(empty, "no header row")) << empty;
    const std::string header_only = load_error("time,x,y,z,qw,qx,qy,qz\n# nothing\n");
    EXPECT_TRUE(contains(header_only, "line 2: no data rows")) << header_only;
}

TEST(TrajectoryCsv, missing_file_is_an_io_error) {
    TempDir dir;
    EXPECT_THROW(load_trajectory_csv(dir.file("absent.csv"), Georef{}), mirage::IoError);
}

TEST(TrajectoryCsv, save_then_load_is_bit_exact) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> coord(-5000, 5000), angle(-3.14, 3.14);
    std::uniform_int_distribution<std::int64_t> step(1, 2'000'000'000);
    std::vector<StampedPose> s;
    GpsTime t{Nanos{1'388'534'418'000'000'123}};
    for (int i = 0; i < 300; ++i) {
        t += Nanos{step(rng)};
        s.push_back({t,
                     {{coord(rng), coord(rng), coord(rng) * 1e-7},
                      quaternion_from_rpy(angle(rng), angle(rng) / 2, angle(rng))}});
    }
    const Trajectory tr(s, Interpolation::Cubic);
    TempDir dir;
    const std::string path = dir.file("saved.csv");
    save_trajectory_csv(path, tr);
    const Trajectory back = load_trajectory_csv(path, Georef{}, Interpolation::Cubic);
    ASSERT_EQ(back.samples().size(), tr.samples().size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        ASSERT_EQ(back.samples()[i].t, tr.samples()[i].t);
        ASSERT_EQ(back.samples()[i].pose.position, tr.samples()[i].pose.position);
        ASSERT_EQ(back.samples()[i].pose.attitude.coeffs(), tr.samples()[i].pose.attitude.coeffs());
    }
    std::ifstream in(path);
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    EXPECT_EQ(header, "time,x,y,z,qw,qx,qy,qz");
    EXPECT_EQ(first.substr(0, first.find(',')), format_decimal_seconds(s[0].t.time_since_epoch()));
}

TEST(TrajectoryCsv, save_to_unwritable_path_is_an_io_error) {
    TempDir dir;
    EXPECT_THROW(save_trajectory_csv(dir.file("no/such/dir.csv"), Trajectory::fixed(Pose{})),
                 mirage::IoError);
}

// The in-memory entry point (fuzz_trajectory_csv) reads exactly what the file reader reads and
// names its input in errors.
TEST(TrajectoryCsv, text_in_memory_reads_like_the_file) {
    const std::string text = "time,x,y,z,qw,qx,qy,qz\n10.5,1,2,3,1,0,0,0\n11,4,5,6,0,0,0,1\n";
    TempDir dir;
    const Trajectory from_file = load_trajectory_csv(write(dir, text), Georef{});
    const Trajectory from_text = parse_trajectory_csv(text, "mem.csv", Georef{});
    ASSERT_EQ(from_text.samples().size(), 2u);
    EXPECT_EQ(from_text.end(), from_file.end());
    EXPECT_EQ(from_text.samples()[1].pose.position, Eigen::Vector3d(4, 5, 6));
    try {
        parse_trajectory_csv("time,x,y,z,qw,qx,qy,qz\n1,1,2\n", "mem.csv", Georef{});
        FAIL() << "short row accepted";
    } catch (const mirage::ConfigError& e) {
        EXPECT_TRUE(contains(e.what(), "trajectory 'mem.csv': line 2: expected 8 fields"))
            << e.what();
    }
}
