// SPDX-License-Identifier: Apache-2.0
#include "seed_writer.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <stdexcept>

namespace mirage::testing::seeds {
namespace {

constexpr std::size_t kMaxSeedBytes = 8192;

// Each fuzz target's test folder (where its CMakeLists.txt calls mirage_add_fuzz).
const std::map<std::string, std::string>& folders() {
    static const std::map<std::string, std::string> m = {
        {"fuzz_velodyne_decode", "tests/emulator/wire/velodyne"},
        {"fuzz_ouster_decode", "tests/emulator/wire/ouster"},
        {"fuzz_ouster_metadata", "tests/emulator/wire/ouster"},
        {"fuzz_nmea", "tests/emulator/nav/nmea"},
        {"fuzz_novatel", "tests/emulator/nav/novatel"},
        {"fuzz_ncom", "tests/emulator/nav/ncom"},
        {"fuzz_navcan", "tests/emulator/nav/can"},
        {"fuzz_candump", "tests/emulator/nav/can"},
        {"fuzz_slcan", "tests/emulator/nav/can"},
        {"fuzz_nav_log", "tests/emulator/nav/protocol"},
        {"fuzz_slcan_bus", "tests/drivers/can"},
        {"fuzz_gsusb", "tests/drivers/can"},
        {"fuzz_pcap_frame", "tests/drivers/pcap"},
        {"fuzz_pcap_reader", "tests/drivers/pcap"},
        {"fuzz_las", "tests/drivers/las"},
        {"fuzz_trajectory_csv", "tests/emulator/core"},
    };
    return m;
}

}  // namespace

void SeedWriter::put(const std::string& target, const std::string& name,
                     std::span<const std::uint8_t> bytes) {
    const auto it = folders().find(target);
    if (it == folders().end()) throw std::runtime_error("seed generator: unknown target " + target);
    // Seeds stay small: libFuzzer mutates them, and the corpora are committed.
    if (bytes.size() > kMaxSeedBytes)
        throw std::runtime_error("seed generator: " + target + "/" + name + " has " +
                                 std::to_string(bytes.size()) + " bytes (at most " +
                                 std::to_string(kMaxSeedBytes) + ")");
    const auto dir = root_ / it->second / "fuzz_seeds" / target;
    if (std::find(cleaned_.begin(), cleaned_.end(), target) == cleaned_.end()) {
        std::filesystem::create_directories(dir);
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.path().filename().string().starts_with("gen_")) std::filesystem::remove(e.path());
        cleaned_.push_back(target);
    }
    std::ofstream out(dir / ("gen_" + name), std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("seed generator: cannot write " + (dir / name).string());
    ++files_;
    bytes_ += bytes.size();
}

void SeedWriter::put(const std::string& target, const std::string& name, std::string_view text) {
    put(target, name, as_bytes(text));
}

void SeedWriter::put(const std::string& target, const std::string& name, std::uint8_t mode,
                     std::span<const std::uint8_t> bytes) {
    std::vector<std::uint8_t> b{mode};
    b.insert(b.end(), bytes.begin(), bytes.end());
    put(target, name, std::span<const std::uint8_t>(b));
}

std::span<const std::uint8_t> as_bytes(std::string_view text) {
    return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

nav::NavSample drive_sample(int k, nav::Protocol source) {
    nav::NavSample s;
    s.source = source;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude | nav::NavSample::kAcceleration |
               nav::NavSample::kAngularRate;
    s.t = core::from_week_time(2300, 302'400'000'000'000 + std::int64_t{k} * 100'000'000);
    s.lat_deg = 47.3769 + 1e-5 * k;
    s.lon_deg = 8.5417 + 2e-5 * k;
    s.height_m = 430.0 + 0.1 * k;
    s.velocity_ned_mps = {1.1, 1.6, -0.05};
    s.roll_rad = 0.02;
    s.pitch_rad = -0.01;
    s.heading_rad = 0.97 + 0.01 * k;
    s.accel_frd_mps2 = {0.1, 0.0, -9.81};
    s.rate_frd_radps = {0.0, 0.0, 0.01};
    s.quality = nav::FixQuality::RtkFixed;
    s.satellites = 14;
    return s;
}

}  // namespace mirage::testing::seeds
