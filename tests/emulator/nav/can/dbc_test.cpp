// SPDX-License-Identifier: Apache-2.0
// Every signal our encoders write, decoded through the DBCs (SBG's own, and our OxTS
// transcription), gives back the physical value we meant.
#include "dbc.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"
#include "test_paths.hpp"
#include "test_units.hpp"

using namespace mirage;

namespace {

using mirage::test::kDeg;

// Checks each signal of each frame against `want` (name -> value, tolerance); returns how many
// signals were compared.
int check_frames(const navcan::Dbc& dbc, const std::vector<nav::CanFrame>& frames,
                 const std::map<std::string, std::pair<double, double>>& want) {
    int n = 0;
    for (const auto& f : frames) {
        const navcan::DbcMessage* m = dbc.message(f.id, f.extended);
        if (!m) {
            ADD_FAILURE() << "no DBC message for 0x" << std::hex << f.id;
            continue;
        }
        EXPECT_EQ(f.len, m->dlc) << m->name;
        for (const auto& sig : m->signals) {
            const auto it = want.find(sig.name);
            if (it == want.end()) continue;
            const auto v = sig.decode(f);
            if (!v) {
                ADD_FAILURE() << sig.name << " does not fit in the frame";
                continue;
            }
            EXPECT_NEAR(*v, it->second.first, it->second.second) << m->name << "." << sig.name;
            ++n;
        }
    }
    return n;
}

}  // namespace

TEST(Dbc, parses_scientific_factors_signs_and_latin1_units) {
    const std::string text =
        "VERSION \"\"\n"
        "BO_ 308 SBG_ECAN_MSG_EKF_POS: 8 Vector__XXX\n"
        " SG_ LONGITUDE : 32|32@1- (1E-007,0) [-214.7483648|214.7483647] \"\xB0\" Vector__XXX\n"
        " SG_ LATITUDE : 0|32@1- (1E-007,0) [-214.7483648|214.7483647] \"\xB0\" Vector__XXX\n"
        "BO_ 2147484672 Ext: 2 X\n"
        " SG_ Q0 : 0|16@1- (3.05185094759972E-005,0) [-1|1] \"\" Vector__XXX\n"
        " SG_ M : 0|8@0+ (1,0) [0|1] \"\" X\n";
    const navcan::Dbc dbc = navcan::Dbc::parse(text);
    ASSERT_EQ(dbc.messages().size(), 2u);
    const auto* pos = dbc.message(308);
    ASSERT_NE(pos, nullptr);
    const auto* lat = pos->signal("LATITUDE");
    ASSERT_NE(lat, nullptr);
    EXPECT_EQ(lat->factor, 1e-7);
    EXPECT_TRUE(lat->is_signed);
    EXPECT_EQ(lat->unit, "\xB0");
    const auto* ext = dbc.message(0x400, true);
    ASSERT_NE(ext, nullptr);
    EXPECT_DOUBLE_EQ(ext->signals[0].factor, 3.05185094759972e-5);
    EXPECT_FALSE(ext->signals[1].little_endian);
    nav::CanFrame f;
    f.id = 308;
    f.len = 8;
    f.data = {0x08, 0x1E, 0xAE, 0x1C, 0xF8, 0xFF, 0xFF, 0xFF};  // 48.1173°, −8e-7°
    EXPECT_NEAR(*lat->decode(f), 48.1173, 1e-12);
    EXPECT_NEAR(*pos->signal("LONGITUDE")->decode(f), -8e-7, 1e-15);
    f.len = 4;
    EXPECT_FALSE(pos->signal("LONGITUDE")->decode(f).has_value());  // beyond the frame
    EXPECT_THROW(navcan::Dbc::parse("BO_ 1 A: 8 X\n SG_ S : 0|8@2+ (1,0) [0|1] \"\" X\n", "t"),
                 ConfigError);
    EXPECT_THROW(navcan::Dbc::parse(" SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n", "t"), ConfigError);
}

TEST(Dbc, every_oxts_signal_we_encode_decodes_through_the_dbc) {
    MIRAGE_NAVIO_OR_SKIP(path, "oxts_rt_min.dbc");
    const navcan::Dbc dbc = navcan::Dbc::load(path);
    ASSERT_EQ(dbc.messages().size(), 6u);
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude;
    // 2031-07-04 13:45:56.78 GPS, as ms since the GPS epoch.
    const std::int64_t ms = 1'624'974'356'780LL;
    s.t = core::GpsTime{core::Nanos{ms * 1'000'000}};
    s.lat_deg = -45.1234567;
    s.lon_deg = -170.7654321;
    s.height_m = -12.345;
    s.velocity_ned_mps = {-12.34, 56.78, 1.5};
    s.heading_rad = 271.23 * kDeg;
    s.pitch_rad = -45.67 * kDeg;
    s.roll_rad = 123.45 * kDeg;
    navcan::OxtsCanIds ids;
    ids.accel_vehicle = ids.rate_vehicle = 0;  // not in the minimal DBC
    const auto frames = navcan::oxts_can_encode(s, ids, -18);
    // Calendar of that GPS time (GPS scale), computed independently from days since 1980-01-06.
    const std::map<std::string, std::pair<double, double>> want = {
        {"TimeYear", {31, 0}},
        {"TimeCentury", {2000, 0}},
        {"TimeMonth", {7, 0}},
        {"TimeDay", {4, 0}},
        {"TimeHSecond", {0.78, 1e-9}},
        {"TimeSecond", {56, 0}},
        {"TimeMinute", {45, 0}},
        {"TimeHour", {13, 0}},
        {"MilliTime", {static_cast<double>(ms), 0}},
        {"UtcOffset", {-18, 0}},
        {"PosLat", {-45.1234567, 1e-9}},
        {"PosLon", {-170.7654321, 1e-9}},
        {"PosAlt", {-12.345, 1e-9}},
        {"VelNorth", {-12.34, 1e-9}},
        {"VelEast", {56.78, 1e-9}},
        {"VelDown", {1.5, 1e-9}},
        {"Speed2D", {std::hypot(12.34, 56.78), 0.005}},
        {"AngleHeading", {271.23, 1e-9}},
        {"AnglePitch", {-45.67, 1e-9}},
        {"AngleRoll", {123.45, 1e-9}},
    };
    EXPECT_EQ(check_frames(dbc, frames, want), static_cast<int>(want.size()));
}

TEST(Dbc, every_sbg_signal_we_encode_decodes_through_sbgs_dbc) {
    MIRAGE_NAVIO_OR_SKIP(path, "sbgCan.dbc");
    const navcan::Dbc dbc = navcan::Dbc::load(path);
    EXPECT_EQ(dbc.messages().size(), 69u);
    navcan::SbgCanEncoderConfig cfg;
    cfg.undulation_m = -23.455;
    cfg.boot = core::parse_time("2025-03-10T08:00:00Z");
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude;
    s.t = core::parse_time("2025-03-10T08:30:15.250Z");
    s.lat_deg = 64.1466;
    s.lon_deg = -21.9426;
    s.height_m = 100.0;
    s.velocity_ned_mps = {1.25, -2.5, -0.75};
    s.roll_rad = 0.1;
    s.pitch_rad = -0.05;
    s.heading_rad = 4.5;  // > π: yaw −1.7832
    auto frames = navcan::sbg_can_encode_utc(s.t, cfg);
    const auto ekf = navcan::sbg_can_encode(s, cfg);
    frames.insert(frames.end(), ekf.begin(), ekf.end());
    const double dev_us = 1815.25e6;
    // 2025-03-10 is a Monday: GPS TOW = 1 day + 08:30:15.250 + 18 s.
    const double tow_ms = (86'400.0 + 8 * 3600 + 30 * 60 + 15.25 + 18) * 1000;
    const double cy = std::cos(-(2 * std::numbers::pi - 4.5) / 2),
                 sy = std::sin(-(2 * std::numbers::pi - 4.5) / 2);
    const double cr = std::cos(0.05), sr = std::sin(0.05), cp = std::cos(-0.025),
                 sp = std::sin(-0.025);
    const std::map<std::string, std::pair<double, double>> want = {
        {"TIME_STAMP", {dev_us, 0}},
        {"GPS_TOW", {tow_ms, 0}},
        {"YEAR", {2025, 0}},
        {"MONTH", {3, 0}},
        {"DAY", {10, 0}},
        {"HOUR", {8, 0}},
        {"MIN", {30, 0}},
        {"SEC", {15, 0}},
        {"MICRO_SEC", {250'000, 0}},
        {"SOLUTION", {0x8F4, 0}},
        {"ROLL", {0.1, 5e-5}},
        {"PITCH", {-0.05, 5e-5}},
        {"YAW", {4.5 - 2 * std::numbers::pi, 5e-5}},
        {"Q0", {cr * cp * cy + sr * sp * sy, 3e-5}},
        {"Q1", {sr * cp * cy - cr * sp * sy, 3e-5}},
        {"Q2", {cr * sp * cy + sr * cp * sy, 3e-5}},
        {"Q3", {cr * cp * sy - sr * sp * cy, 3e-5}},
        {"LATITUDE", {64.1466, 1e-9}},
        {"LONGITUDE", {-21.9426, 1e-9}},
        {"ALTITUDE", {123.455, 1e-9}},
        {"UNDULATION", {-23.455, 0.0025}},
        {"VELOCITY_N", {1.25, 1e-9}},
        {"VELOCITY_E", {-2.5, 1e-9}},
        {"VELOCITY_D", {-0.75, 1e-9}},
    };
    // TIME_STAMP appears in UTC_0 and EKF_INFO: UTC_0's is the device time of the whole ms,
    // which here equals the sample's.
    EXPECT_EQ(check_frames(dbc, frames, want), static_cast<int>(want.size()) + 1);
}
