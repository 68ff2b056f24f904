// SPDX-License-Identifier: Apache-2.0
// DIS from an independent encoder (issue 22 item 5): open-dis (npm) sends Entity State PDUs of a
// car circling the walled yard, five a second, over loopback UDP to `mirage live --nav dis:…`,
// which dead-reckons between them. Every Velodyne point, put in the world with the TRUTH pose
// at its own timestamp, must lie on the yard's walls or ground, as in the other protocols' runs.
// The PDU fields are worked out here from the truth on their own (points of the scene frame
// mapped to ECEF, not Mirage's DIS code); the bytes are open-dis's.
#include <gtest/gtest.h>

#include <GeographicLib/Geocentric.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "background_mirage.hpp"
#include "live_yard.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

// One PDU's fields in ECEF, from the truth pose at time `t` (seconds into the trajectory).
struct Fields {
    Eigen::Vector3d location, velocity, acceleration, omega_body;
    Eigen::Matrix3d body;  // DIS body axes (x forward, y right, z down) in ECEF
};

class TruthInEcef {
  public:
    TruthInEcef(const core::Trajectory& truth, const core::Georef& georef)
        : truth_(truth), geo_(georef) {}

    Eigen::Vector3d ecef(const Eigen::Vector3d& local) const {
        const Eigen::Vector3d g = geo_.geodetic_from_local(local);
        Eigen::Vector3d x;
        GeographicLib::Geocentric::WGS84().Forward(g.x(), g.y(), g.z(), x.x(), x.y(), x.z());
        return x;
    }
    // Body axes: scene directions of forward, left, up carried to ECEF by mapping points 1 m
    // either side (the projection is conformal: angles survive), then y = −left, z = −up.
    Eigen::Matrix3d body(double t) const {
        const core::Pose p = pose(t);
        Eigen::Matrix3d b;
        for (int a = 0; a < 3; ++a) {
            const Eigen::Vector3d d = p.attitude * Eigen::Vector3d::Unit(a);
            const Eigen::Vector3d e = (ecef(p.position + d) - ecef(p.position - d)).normalized();
            b.col(a) = a == 0 ? e : Eigen::Vector3d(-e);
        }
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(b, Eigen::ComputeFullU | Eigen::ComputeFullV);
        return svd.matrixU() * svd.matrixV().transpose();  // the nearest rotation
    }
    Fields at(double t) const {
        const double h = 0.005;
        Fields f;
        f.location = ecef(pose(t).position);
        const Eigen::Vector3d before = ecef(pose(t - h).position),
                              after = ecef(pose(t + h).position);
        f.velocity = (after - before) / (2 * h);
        f.acceleration = (after - 2 * f.location + before) / (h * h);
        f.body = body(t);
        const Eigen::AngleAxisd turn(body(t - h).transpose() * body(t + h));
        f.omega_body = turn.axis() * (turn.angle() / (2 * h));
        return f;
    }

  private:
    core::Pose pose(double t) const {
        return truth_.at(truth_.begin() + core::Nanos(static_cast<std::int64_t>(t * 1e9)));
    }
    const core::Trajectory& truth_;
    core::GeodeticConverter geo_;
};

// DIS Euler angles of a body-to-ECEF rotation: R = Rz(ψ)·Ry(θ)·Rx(φ).
Eigen::Vector3d psi_theta_phi(const Eigen::Matrix3d& r) {
    return {std::atan2(r(1, 0), r(0, 0)), -std::asin(r(2, 0)), std::atan2(r(2, 1), r(2, 2))};
}

// DIS absolute timestamp: UTC seconds past the hour in units of 3600/2³¹ s, lowest bit set.
std::uint32_t absolute_timestamp(core::GpsTime t) {
    const std::int64_t hour = 3'600'000'000'000;
    const double past = double(core::unix_ns_from_gps(t) % hour) * 1e-9;
    const auto units = static_cast<std::uint32_t>(past / 3600.0 * 2147483648.0);
    return (units << 1) | 1u;
}

// One CSV line for dis_sender.js: PDU k of the run, alternating RVW (4: world velocity and
// acceleration) and RPB (7: velocity in body axes), so both frames carry the car between PDUs.
// `lift_m` moves the location up (a decoy entity elsewhere).
std::string row(const TruthInEcef& truth, core::GpsTime t0, double t, std::uint16_t entity,
                double lift_m = 0) {
    Fields f = truth.at(t);
    f.location += lift_m * f.location.normalized();
    const core::GpsTime at = t0 + core::Nanos(static_cast<std::int64_t>(t * 1e9));
    const int k = static_cast<int>(std::lround(t / 0.2));
    const int algorithm = k % 2 == 0 ? 4 : 7;
    const Eigen::Vector3d v =
        algorithm == 7 ? Eigen::Vector3d(f.body.transpose() * f.velocity) : f.velocity;
    const Eigen::Vector3d a = algorithm == 4 ? f.acceleration : Eigen::Vector3d::Zero();
    const Eigen::Vector3d e = psi_theta_phi(f.body);
    char line[512];
    std::snprintf(line, sizeof line,
                  "%lld,1,1,2,%u,%u,%d,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%.8f,%.8f,%.8f,%.6f,%.6f,%.6f,"
                  "%.8f,%.8f,%.8f\n",
                  static_cast<long long>(core::unix_ns_from_gps(at) / 1'000'000), entity,
                  absolute_timestamp(at), algorithm, v.x(), v.y(), v.z(), f.location.x(),
                  f.location.y(), f.location.z(), e.x(), e.y(), e.z(), a.x(), a.y(), a.z(),
                  f.omega_body.x(), f.omega_body.y(), f.omega_body.z());
    return line;
}

const std::string kModules = MIRAGE_PEERS_DIR;

void run_peer_case(const std::string& version) {
    if (!std::filesystem::exists(kModules + "/open-dis/dist/dis7.min.js"))
        GTEST_SKIP()
            << "open-dis not installed in " << kModules
            << ": run scripts/install-peers <build> (needs node, npm and the npm registry)";
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    const core::Georef georef = core::Georef::projected(32632, {500000, 5000000, 0});
    const core::Trajectory truth =
        core::load_trajectory_csv(traj, georef, core::Interpolation::Cubic);
    const TruthInEcef ecef(truth, georef);

    Collector rx;
    BackgroundMirage live = start_mirage(
        "live --scene " + scene +
        " --nav 'dis:udp://127.0.0.1:0?exercise=1&entity=1.2.7' --sensor vlp16 --sub-rays 1"
        " --no-noise --position-port 0 --duration 3 --no-status --first-nav-timeout 15"
        " --max-extrapolation-ms 150 --to 127.0.0.1 --data-port " +
        std::to_string(rx.port()));
    std::smatch m;
    const std::string l = live.wait_for(std::regex("udp port [0-9]+"));
    ASSERT_TRUE(std::regex_search(l, m, std::regex("udp port ([0-9]+)"))) << live.output;

    // PDUs every 200 ms for 6 s after a whole second ≥ 1 s ahead, each sent at its own time;
    // between them, six PDUs of another entity (1.2.8, 1 km up) that live must ignore.
    const auto now = core::gps_from_unix_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::system_clock::now().time_since_epoch())
                                                .count());
    const core::GpsTime t0(std::chrono::duration_cast<std::chrono::seconds>(
        now.time_since_epoch() + std::chrono::seconds(2)));
    {
        std::ofstream csv(tmp.file("pdus.csv"));
        for (int k = 1; k <= 30; ++k) {  // from 0.2 s: the differences need truth either side
            csv << row(ecef, t0, 0.2 * k, 7);
            if (k % 5 == 2) csv << row(ecef, t0, 0.2 * k + 0.1, 8, 1000);
        }
    }
    BackgroundMirage sender;
    sender.pipe =
        ::popen(("node " + std::string(MIRAGE_PEER_SCRIPTS) + "/dis_sender.js " + kModules + " " +
                 version + " " + tmp.file("pdus.csv") + " " + m[1].str() + " 2>&1")
                    .c_str(),
                "r");
    const int sender_rc = sender.finish();
    const int live_rc = live.finish();
    rx.stop();
    ASSERT_EQ(sender_rc, 0) << sender.output;
    ASSERT_EQ(live_rc, 0) << live.output;
    const Stats st = check_points(rx.packets(), truth, t0);
    std::printf(
        "[ dis %s from open-dis ] %zu packets, %zu points: distance to the yard median %.4f m, "
        "p99 %.4f m, max %.4f m, RMS %.4f m\n%s%s",
        version.c_str(), st.packets, st.points, st.median, st.p99, st.max, st.rms,
        sender.output.c_str(), live.output.c_str());
    EXPECT_NE(sender.output.find("sent 36 PDUs"), std::string::npos) << sender.output;
    EXPECT_EQ(st.bad_packets, 0u);
    EXPECT_GT(st.packets, 2100u);
    EXPECT_GT(st.points, 200'000u);
    EXPECT_LT(st.median, 0.01);
    EXPECT_LT(st.p99, 0.02);
    EXPECT_NE(live.output.find("stale windows 0 in 0 periods"), std::string::npos) << live.output;
    EXPECT_NE(live.output.find("dis entity 1.2.7"), std::string::npos) << live.output;
    // Live stops after 3 s; the decoys sent by then (at 0.5, 1.5, 2.5 s …) are counted, not used.
    std::smatch others;
    ASSERT_TRUE(std::regex_search(live.output, others, std::regex("other entities ([0-9]+)")));
    EXPECT_GE(std::stoi(others[1].str()), 2) << live.output;
    EXPECT_NE(live.output.find("pose rejected 0 "), std::string::npos) << live.output;
}

TEST(LiveDisPeer, open_dis_version_7_pdus_drive_live_onto_the_yard) { run_peer_case("7"); }
TEST(LiveDisPeer, open_dis_version_6_pdus_drive_live_onto_the_yard) { run_peer_case("6"); }

}  // namespace
}  // namespace mirage::test
