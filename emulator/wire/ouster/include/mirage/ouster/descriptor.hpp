// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mirage::sensor {
struct SensorModel;
}

namespace mirage::ouster {

enum class ProductLine : std::uint8_t { OS0, OS1, OS2 };

// udp_profile_lidar (docs/wire-formats.md §2.2).
enum class Profile : std::uint8_t {
    Legacy,               // "LEGACY": no packet header/footer, 16-byte column header + status
    Rng19Rfl8Sig16Nir16,  // "RNG19_RFL8_SIG16_NIR16": 12-byte pixels, 1 mm range
    Rng15Rfl8Nir8,        // "RNG15_RFL8_NIR8": 4-byte pixels, 8 mm range, NIR × 16
};

// What the last 8 bytes of a non-legacy packet carry (§2.5): a CRC-64/XZ (FW 3.x) or the
// FW 2.x constant placeholder 0xDEADBEEF0000C0DE after 24 zero bytes.
enum class FooterKind : std::uint8_t { Crc64, Fw2Placeholder };

inline constexpr std::uint64_t kFw2FooterWord = 0xDEADBEEF0000C0DEull;
inline constexpr std::uint32_t kEncoderTicksPerRev = 90112;  // §2.3
inline constexpr std::uint16_t kPacketTypeLidar = 0x0001;

// Columns per frame × frames per second ("1024x10").
struct LidarMode {
    std::uint16_t columns = 1024;
    std::uint8_t hz = 10;
    bool operator==(const LidarMode&) const = default;
};

std::string to_string(ProductLine p);  // "OS-1"
std::string to_string(Profile p);      // "RNG19_RFL8_SIG16_NIR16"
std::string to_string(LidarMode m);    // "1024x10"
// Throw ConfigError "ouster: unknown … '<text>' (known: …)".
Profile parse_profile(std::string_view text);
LidarMode parse_lidar_mode(std::string_view text);

// One descriptor serves encoder, decoder, metadata and statistics.
struct Descriptor {
    ProductLine line = ProductLine::OS1;
    std::uint16_t beams = 64;  // pixels per column H
    LidarMode mode{};
    Profile profile = Profile::Legacy;
    std::uint16_t columns_per_packet = 16;
    FooterKind footer = FooterKind::Crc64;

    // Beam intrinsics (§2.7), row 0 = top beam; degrees.
    std::vector<double> altitude_deg;
    std::vector<double> azimuth_deg;
    double beam_origin_mm = 15.806;  // lidar_origin_to_beam_origin_mm = beam_to_lidar(0,3)
    double beam_z_mm = 0;            // beam_to_lidar(2,3)
    // Row-major 4×4, mm (§2.7 defaults; OS-2 units carry their own lidar z).
    std::array<double, 16> lidar_to_sensor{-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1};
    std::array<double, 16> imu_to_sensor{1, 0, 0, 6.253, 0, 1, 0, -11.775,
                                         0, 0, 1, 7.645, 0, 0, 0, 1};

    // Identity; the packet header and the JSON must agree (§2.5 validation).
    std::uint64_t serial = 992000000001;  // 40 bits
    std::uint32_t init_id = 0x100001;     // 24 bits
    std::string firmware = "v3.0.1";
    std::string part_number = "840-000000-00";
    std::uint16_t udp_port_lidar = 7502;
    std::uint16_t udp_port_imu = 7503;

    // Header status bytes of non-legacy packets (§2.4).
    std::uint8_t thermal_shutdown_countdown = 0;
    std::uint8_t shot_limiting_countdown = 0;
    std::uint8_t thermal_shutdown_status = 0;
    std::uint8_t shot_limiting_status = 0;

    // Derived sizes (§2.2).
    std::size_t pixel_bytes() const;
    std::size_t packet_header_bytes() const;
    std::size_t column_header_bytes() const;
    std::size_t column_footer_bytes() const;
    std::size_t packet_footer_bytes() const;
    std::size_t column_bytes() const;
    std::size_t packet_bytes() const;
    std::uint32_t packets_per_frame() const { return mode.columns / columns_per_packet; }
    double column_period_ns() const { return 1e9 / (double(mode.columns) * mode.hz); }
    // Encoder count of a column: measurement ID × 90112 / W (88 per column at W = 1024).
    std::uint32_t encoder_count(std::uint16_t measurement_id) const;
    // "OS-1-64"
    std::string prod_line() const;
    // {12, 8, 4, 0}-like destaggering shifts: round((az − min az)/360°·W) per row.
    std::vector<int> pixel_shift_by_row() const;
};

// A descriptor for a product/beam/mode/profile, with the beam table of the matching Mirage preset
// (sensor::preset "os<P>-<H>-<W>x<F>") and the product's §2.7 defaults (beam origin 27.67 /
// 15.806 / 13.762 mm; OS-2 lidar z 78.296 mm and IMU z 11.645 mm as on the §6 capture).
// Throws ConfigError on a combination the products lack or a columns-per-packet that does not
// divide the frame.
Descriptor make_descriptor(ProductLine line, int beams, LidarMode mode, Profile profile,
                           int columns_per_packet = 16);
// From a preset name ("os1-64-1024x10", "os2-128-2048x10") and a profile.
Descriptor make_descriptor(const std::string& preset_name, Profile profile);
// Beam table and timing from any Ouster-family SensorModel (a YAML file based on a preset).
// Throws ConfigError when the model is not a spinning Ouster pattern with 32/64/128 beams.
Descriptor descriptor_from_model(const sensor::SensorModel& model, ProductLine line,
                                 Profile profile);

}  // namespace mirage::ouster
