// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mirage::las {

struct LasHeaderInfo {
    std::uint8_t version_major = 0, version_minor = 0;
    std::uint16_t global_encoding = 0;
    std::uint8_t point_format = 0;
    std::uint16_t record_length = 0;
    std::uint32_t offset_to_points = 0;
    std::uint32_t vlr_count = 0;
    std::uint64_t point_count = 0;                 // LAS 1.4 64-bit field
    std::uint32_t legacy_point_count = 0;
    std::array<std::uint64_t, 15> points_by_return{};
    std::array<double, 3> scale{}, offset{}, min{}, max{};
    std::string wkt;                               // from the WKT VLR, if any
};

struct LasPoint {
    double x, y, z;           // scaled and offset
    std::uint16_t intensity;
    std::uint8_t return_number, number_of_returns, classification;
    float scan_angle_deg;
    std::uint16_t point_source_id;
    double gps_time;
    std::uint16_t red, green, blue;
};

// Reads a LAS 1.2–1.4 file (formats 0–3, 6–8) fully; validate() lists every problem found
// (sizes, signature, counts vs file length, counts by return, bounds vs points, scale > 0…).
class LasFile {
public:
    static LasFile read(const std::string& path);   // throws IoError if unreadable
    const LasHeaderInfo& header() const { return header_; }
    const std::vector<LasPoint>& points() const { return points_; }
    std::vector<std::string> validate() const;      // empty when valid

private:
    LasHeaderInfo header_;
    std::vector<LasPoint> points_;
    std::vector<std::string> problems_;   // found while reading
    std::uint64_t file_size_ = 0;
};

}  // namespace mirage::las
