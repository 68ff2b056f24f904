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
    std::uint64_t point_count = 0;  // LAS 1.4 64-bit field
    std::uint32_t legacy_point_count = 0;
    std::array<std::uint64_t, 15> points_by_return{};
    std::array<std::uint32_t, 5> legacy_points_by_return{};
    std::array<double, 3> scale{}, offset{}, min{}, max{};
    std::string wkt;  // from the WKT VLR, if any
    // Additions beyond the original contract.
    char signature[4] = {0, 0, 0, 0};
    std::uint16_t file_source_id = 0;
    std::uint16_t header_size = 0;
    std::uint16_t creation_day = 0, creation_year = 0;
    std::string system_identifier, generating_software;
    std::uint64_t start_of_first_evlr = 0;
    std::uint32_t evlr_count = 0;
    bool has_wkt_vlr = false;
};

struct LasPoint {
    double x, y, z;  // scaled and offset
    std::uint16_t intensity;
    std::uint8_t return_number, number_of_returns, classification;
    float scan_angle_deg;
    std::uint16_t point_source_id;
    double gps_time;
    std::uint16_t red, green, blue;
    // Additions beyond the original contract.
    std::int32_t raw_x, raw_y, raw_z;  // stored integers before scale and offset
    std::uint8_t scan_direction, edge_of_flight_line;
    std::uint8_t scanner_channel;  // formats 6+ only
};

// Reads a LAS 1.2–1.4 file (formats 0–3, 6–8) fully; validate() lists every problem found
// (sizes, signature, counts vs file length, counts by return, bounds vs points, scale > 0…).
// A corrupt file never makes it read out of bounds: fields past the end read as absent, and
// only the whole records actually present are decoded (min of header count and file room).
class LasFile {
  public:
    static LasFile read(const std::string& path);  // throws IoError if unreadable
    // The same from a file's bytes in memory (read() uses it).
    static LasFile from_bytes(const std::vector<std::uint8_t>& bytes);
    const LasHeaderInfo& header() const { return header_; }
    const std::vector<LasPoint>& points() const { return points_; }
    std::vector<std::string> validate() const;  // empty when valid
    // Whole records between the point-data offset and the end of the file (or first EVLR).
    std::uint64_t records_in_file() const { return records_in_file_; }
    std::uint64_t file_size() const { return file_size_; }

  private:
    LasHeaderInfo header_;
    std::vector<LasPoint> points_;
    std::vector<std::string> problems_;  // found while reading
    std::uint64_t file_size_ = 0;
    std::uint64_t records_in_file_ = 0;

    void parse(const std::vector<std::uint8_t>& bytes);
};

}  // namespace mirage::las
