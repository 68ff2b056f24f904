// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/descriptor.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "mirage/core/error.hpp"
#include "mirage/sensor/spinning.hpp"

namespace mirage::ouster {
namespace {

constexpr std::array<std::string_view, 3> kProfileNames = {"LEGACY", "RNG19_RFL8_SIG16_NIR16",
                                                           "RNG15_RFL8_NIR8"};
constexpr std::array<LidarMode, 6> kModes = {
    {{512, 10}, {512, 20}, {1024, 10}, {1024, 20}, {2048, 10}, {2048, 20}}};

int product_index(ProductLine p) { return static_cast<int>(p); }

}  // namespace

std::string to_string(ProductLine p) { return "OS-" + std::to_string(product_index(p)); }

std::string to_string(Profile p) { return std::string(kProfileNames[static_cast<std::size_t>(p)]); }

std::string to_string(LidarMode m) {
    return std::to_string(m.columns) + "x" + std::to_string(m.hz);
}

Profile parse_profile(std::string_view text) {
    for (std::size_t i = 0; i < kProfileNames.size(); ++i)
        if (text == kProfileNames[i]) return static_cast<Profile>(i);
    std::string known;
    for (auto n : kProfileNames) known += (known.empty() ? "" : ", ") + std::string(n);
    throw ConfigError("ouster: unknown lidar profile '" + std::string(text) + "' (known: " + known +
                      ")");
}

LidarMode parse_lidar_mode(std::string_view text) {
    std::string known;
    for (const auto& m : kModes) {
        if (text == to_string(m)) return m;
        known += (known.empty() ? "" : ", ") + to_string(m);
    }
    throw ConfigError("ouster: unknown lidar mode '" + std::string(text) + "' (known: " + known +
                      ")");
}

std::size_t Descriptor::pixel_bytes() const { return profile == Profile::Rng15Rfl8Nir8 ? 4 : 12; }
std::size_t Descriptor::packet_header_bytes() const { return profile == Profile::Legacy ? 0 : 32; }
std::size_t Descriptor::column_header_bytes() const { return profile == Profile::Legacy ? 16 : 12; }
std::size_t Descriptor::column_footer_bytes() const { return profile == Profile::Legacy ? 4 : 0; }
std::size_t Descriptor::packet_footer_bytes() const { return profile == Profile::Legacy ? 0 : 32; }
std::size_t Descriptor::column_bytes() const {
    return column_header_bytes() + std::size_t{beams} * pixel_bytes() + column_footer_bytes();
}
std::size_t Descriptor::packet_bytes() const {
    return packet_header_bytes() + std::size_t{columns_per_packet} * column_bytes() +
           packet_footer_bytes();
}

std::uint32_t Descriptor::encoder_count(std::uint16_t measurement_id) const {
    return static_cast<std::uint32_t>(std::uint64_t{measurement_id} * kEncoderTicksPerRev /
                                      mode.columns);
}

std::string Descriptor::prod_line() const { return to_string(line) + "-" + std::to_string(beams); }

std::vector<int> Descriptor::pixel_shift_by_row() const {
    std::vector<int> shift(azimuth_deg.size(), 0);
    if (azimuth_deg.empty()) return shift;
    const double lo = *std::min_element(azimuth_deg.begin(), azimuth_deg.end());
    for (std::size_t r = 0; r < azimuth_deg.size(); ++r)
        shift[r] = static_cast<int>(std::lround((azimuth_deg[r] - lo) / 360.0 * mode.columns));
    return shift;
}

Descriptor descriptor_from_model(const sensor::SensorModel& model, ProductLine line,
                                 Profile profile) {
    const auto* spin = dynamic_cast<const sensor::SpinningPattern*>(model.scan.get());
    const std::string who = "ouster: sensor '" + model.name + "'";
    if (!spin || spin->config().family != sensor::SpinningFamily::Ouster)
        throw ConfigError(who + ": not an Ouster spinning pattern");
    const auto& cfg = spin->config();
    const auto beams = cfg.lasers.size();
    if (beams != 32 && beams != 64 && beams != 128)
        throw ConfigError(who + ": " + std::to_string(beams) + " beams (Ouster: 32, 64 or 128)");
    const double cols = 1e9 / (cfg.sequence_period_ns * cfg.rotation_hz);
    LidarMode mode{static_cast<std::uint16_t>(std::lround(cols)),
                   static_cast<std::uint8_t>(std::lround(cfg.rotation_hz))};
    if (std::find(kModes.begin(), kModes.end(), mode) == kModes.end() ||
        std::abs(cols - mode.columns) > 1e-6 || std::abs(cfg.rotation_hz - mode.hz) > 1e-9)
        throw ConfigError(who + ": column period and rotation rate match no Ouster lidar mode");
    Descriptor d;
    d.line = line;
    d.beams = static_cast<std::uint16_t>(beams);
    d.mode = mode;
    d.profile = profile;
    for (const auto& l : cfg.lasers) {
        d.altitude_deg.push_back(l.elevation_deg);
        d.azimuth_deg.push_back(l.azimuth_offset_deg);
    }
    switch (line) {
        case ProductLine::OS0:
            d.beam_origin_mm = 27.67;
            break;
        case ProductLine::OS1:
            d.beam_origin_mm = 15.806;
            break;
        case ProductLine::OS2:
            d.beam_origin_mm = 13.762;
            d.lidar_to_sensor[11] = 78.296;  // §6 OS-2-128 JSON
            d.imu_to_sensor[11] = 11.645;
            break;
    }
    // Stable made-up identity per product/beams (JSON and headers carry the same values).
    d.serial = 992000000000ull + std::uint64_t(product_index(line)) * 1000 + beams;
    d.init_id = 0x5A0000u + static_cast<std::uint32_t>(product_index(line) * 256) +
                static_cast<std::uint32_t>(beams);
    return d;
}

Descriptor make_descriptor(ProductLine line, int beams, LidarMode mode, Profile profile,
                           int columns_per_packet) {
    if (beams != 32 && beams != 64 && beams != 128)
        throw ConfigError("ouster: " + std::to_string(beams) + " beams (known: 32, 64, 128)");
    if (std::find(kModes.begin(), kModes.end(), mode) == kModes.end())
        throw ConfigError("ouster: unsupported lidar mode '" + to_string(mode) + "'");
    if (columns_per_packet < 1 || columns_per_packet > mode.columns ||
        mode.columns % columns_per_packet != 0)
        throw ConfigError("ouster: columns_per_packet " + std::to_string(columns_per_packet) +
                          " does not divide " + std::to_string(mode.columns) + " columns");
    const std::string name = "os" + std::to_string(product_index(line)) + "-" +
                             std::to_string(beams) + "-" + to_string(mode);
    Descriptor d = descriptor_from_model(sensor::preset(name), line, profile);
    d.columns_per_packet = static_cast<std::uint16_t>(columns_per_packet);
    return d;
}

Descriptor make_descriptor(const std::string& preset_name, Profile profile) {
    const auto fail = [&] {
        throw ConfigError("ouster: '" + preset_name + "' is not an Ouster preset (os<0|1|2>-<32|" +
                          "64|128>-<W>x<F>)");
    };
    if (preset_name.size() < 4 || preset_name.compare(0, 2, "os") != 0) fail();
    const char p = preset_name[2];
    if (p < '0' || p > '2' || preset_name[3] != '-') fail();
    const auto line = static_cast<ProductLine>(p - '0');
    Descriptor d = descriptor_from_model(sensor::preset(preset_name), line, profile);
    return d;
}

}  // namespace mirage::ouster
