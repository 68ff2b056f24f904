// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mirage::las {

// A waveform packet descriptor VLR (LASF_Spec 100–354; docs/file-formats.md §6.1).
struct WaveDescriptorInfo {
    std::uint8_t index = 0;  // record id − 99
    std::uint8_t bits = 0, compression = 0;
    std::uint32_t samples = 0, spacing_ps = 0;
    double gain = 0, offset = 0;
};

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
    std::uint64_t start_of_waveform = 0;
    std::vector<WaveDescriptorInfo> wave_descriptors;
    std::vector<std::string> extra_bytes_names;   // from the Extra Bytes VLR, in record order
    std::vector<std::uint8_t> extra_bytes_types;  // and their data types (9: float)
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
    // Formats 4, 5, 9, 10.
    std::uint8_t wave_index;
    std::uint64_t wave_offset;
    std::uint32_t wave_size;
    float wave_location_ps, wave_dx, wave_dy, wave_dz;
    // Mirage's echo fields (extra bytes "amplitude", "echo width", "deviation"), else 0.
    float amplitude, echo_width_ns, deviation;
    // Mirage's photon-event fields (extra bytes "pixel", "event", "time of flight"), else 0.
    std::uint32_t pixel;
    std::uint8_t event;
    double time_of_flight_ns;
};

// Reads a LAS 1.2–1.4 file (formats 0–10) fully, with its waveform packets (from the EVLR, or
// the .wdp file beside it when global encoding bit 2 says they are external); validate() lists
// every problem found (sizes, signature, counts vs file length, counts by return, bounds vs points,
// scale > 0…). A corrupt file never makes it read out of bounds: fields past the end read as
// absent, and only the whole records actually present are decoded (min of header count and file
// room).
class LasFile {
  public:
    static LasFile read(const std::string& path);  // throws IoError if unreadable
    // The same from a file's bytes in memory (read() uses it).
    static LasFile from_bytes(const std::vector<std::uint8_t>& bytes);
    // With an external waveform file's bytes (`wdp`: nullptr when there is none).
    static LasFile from_bytes(const std::vector<std::uint8_t>& bytes,
                              const std::vector<std::uint8_t>* wdp);
    const LasHeaderInfo& header() const { return header_; }
    const std::vector<LasPoint>& points() const { return points_; }
    std::vector<std::string> validate() const;  // empty when valid
    // Whole records between the point-data offset and the end of the file (or first EVLR).
    std::uint64_t records_in_file() const { return records_in_file_; }
    std::uint64_t file_size() const { return file_size_; }
    // A point's waveform samples (empty when it has none or its packet is not valid).
    std::vector<std::uint32_t> waveform(const LasPoint& p) const;
    const WaveDescriptorInfo* descriptor(std::uint8_t index) const;

  private:
    LasHeaderInfo header_;
    std::vector<LasPoint> points_;
    std::vector<std::string> problems_;  // found while reading
    std::uint64_t file_size_ = 0;
    std::uint64_t records_in_file_ = 0;
    std::vector<std::uint8_t> waves_;  // the waveform packet record, its EVLR header first

    void parse(const std::vector<std::uint8_t>& bytes);
    // las_reader_waveforms.cpp
    void read_vlr(const std::uint8_t* v, const std::string& user, std::uint16_t id,
                  std::uint16_t len);
    void load_waves(const std::vector<std::uint8_t>& bytes, const std::vector<std::uint8_t>* wdp);
    void check_waves();
};

}  // namespace mirage::las
