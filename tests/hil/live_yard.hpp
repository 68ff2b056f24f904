// SPDX-License-Identifier: Apache-2.0
// The walled yard the live end-to-end tests drive through: its scene, a circling trajectory, a
// collector of the Velodyne packets `mirage live` sends, and the check that every decoded point,
// put in the world with the TRUTH pose at its own timestamp, lies on the yard's walls or ground.
#pragma once
#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "mirage/core/georef.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/velodyne/data_packet.hpp"

namespace mirage::test {

// A 80 x 80 m walled yard in UTM 32N: ground z = 0, inner wall faces at x, y = ±40.
constexpr const char* kScene = R"(georef: {epsg: 32632, anchor: [500000, 5000000, 0]}
materials:
  ground: {reflectance: 0.3, classification: 2}
  wall: {reflectance: 0.5, classification: 6}
objects:
  - {type: plane, material: ground, size: [120, 120]}
  - {type: box, material: wall, size: [82, 1, 20], transform: {translate: [0, 40.5, 10]}}
  - {type: box, material: wall, size: [82, 1, 20], transform: {translate: [0, -40.5, 10]}}
  - {type: box, material: wall, size: [1, 82, 20], transform: {translate: [40.5, 0, 10]}}
  - {type: box, material: wall, size: [1, 82, 20], transform: {translate: [-40.5, 0, 10]}}
)";

inline double distance_to_yard(const Eigen::Vector3d& p) {
    return std::min({std::abs(p.z()), std::abs(p.x() - 40), std::abs(p.x() + 40),
                     std::abs(p.y() - 40), std::abs(p.y() + 40)});
}

// A car circling at 6 m/s on a 15 m radius (yaw rate 0.4 rad/s), 40 s of samples every 50 ms.
inline void write_trajectory(const std::string& path) {
    std::ofstream f(path);
    f << "time,x,y,z,roll,pitch,yaw\n";
    for (int i = 0; i <= 800; ++i) {
        const double t = 0.05 * i, a = 0.4 * t;
        f << t << ',' << 15 * std::cos(a) << ',' << 15 * std::sin(a) << ",1.8,0,0,"
          << (a + M_PI / 2) * 180 / M_PI << '\n';
    }
}

// Collects datagrams on a thread until `stop`.
// The circle written by write_trajectory, read back as the truth (cubic, the yard's georef).
inline core::Trajectory circle_truth(const std::string& path) {
    return core::load_trajectory_csv(path, core::Georef::projected(32632, {500000, 5000000, 0}),
                                     core::Interpolation::Cubic);
}

// "t0 gps:<s>" from `mirage fake-ins`: the instant its trajectory starts.
inline core::GpsTime parse_t0(const std::string& line) {
    std::smatch m;
    if (!std::regex_search(line, m, std::regex("t0 gps:([0-9]+\\.[0-9]+)"))) return {};
    return core::GpsTime(*core::parse_decimal_seconds(m[1].str()));
}

class Collector {
  public:
    Collector() : thread_([this] { run(); }) {}
    ~Collector() { stop(); }
    void stop() {
        stop_ = true;
        if (thread_.joinable()) thread_.join();
    }
    std::uint16_t port() const { return rx_.port(); }
    const std::vector<std::vector<std::uint8_t>>& packets() const { return packets_; }
    // Kernel receive time (CLOCK_REALTIME ns, 0 if none) of each of packets().
    const std::vector<std::int64_t>& kernel_times() const { return kernel_times_; }

  private:
    void run() {
        udp::ReceivedDatagram d;
        while (!stop_)
            if (rx_.receive(d, std::chrono::milliseconds(50))) {
                packets_.push_back(d.payload);
                kernel_times_.push_back(d.kernel_time_ns);
            }
    }
    udp::UdpReceiver rx_;
    std::atomic<bool> stop_{false};
    std::vector<std::vector<std::uint8_t>> packets_;
    std::vector<std::int64_t> kernel_times_;
    std::thread thread_;
};

struct Stats {
    std::size_t points = 0, packets = 0, bad_packets = 0;
    double median = 0, p99 = 0, max = 0, rms = 0;
};

inline Stats check_points(const std::vector<std::vector<std::uint8_t>>& packets,
                          const core::Trajectory& truth, core::GpsTime t0,
                          const core::Pose& mount = {}) {
    Stats st;
    std::vector<double> err;
    // Velodyne time is µs past the UTC hour: take the hour from t0 (a run lasts seconds).
    const std::int64_t t0_unix = core::unix_ns_from_gps(t0);
    const std::int64_t hour_ns = 3'600'000'000'000;
    velodyne::DecodedPacket dp;
    for (const auto& p : packets) {
        if (p.size() != 1206) continue;
        if (velodyne::decode_data(p, nullptr, dp) != velodyne::DecodeStatus::Ok) {
            ++st.bad_packets;
            continue;
        }
        ++st.packets;
        std::int64_t hour = t0_unix / hour_ns * hour_ns;
        std::int64_t unix_t = hour + std::int64_t(dp.timestamp_us) * 1000;
        if (unix_t < t0_unix - hour_ns / 2) unix_t += hour_ns;  // the hour rolled during the run
        for (const auto& f : dp.firing) {
            if (f.distance_m <= 0) continue;
            const core::GpsTime t = core::gps_from_unix_ns(unix_t + f.time_offset_ns);
            const core::Pose pose = truth.at(truth.begin() + (t - t0)) * mount;  // sensor's
            err.push_back(distance_to_yard(pose.apply(Eigen::Vector3d(f.x, f.y, f.z))));
        }
    }
    st.points = err.size();
    if (err.empty()) return st;
    std::sort(err.begin(), err.end());
    st.median = err[err.size() / 2];
    st.p99 = err[err.size() * 99 / 100];
    st.max = err.back();
    double s2 = 0;
    for (double e : err) s2 += e * e;
    st.rms = std::sqrt(s2 / double(err.size()));
    return st;
}

}  // namespace mirage::test
