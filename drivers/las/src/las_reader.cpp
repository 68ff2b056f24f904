// SPDX-License-Identifier: Apache-2.0
#include "mirage/las/las_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "las_layout.hpp"
#include "mirage/core/error.hpp"
#include "wdp_file.hpp"

namespace mirage::las {
namespace {

using namespace layout;

constexpr const char* kAxis[3] = {"x", "y", "z"};

std::string printable(const char* s, std::size_t n) {
    std::string out;
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        out += (c >= 32 && c < 127) ? std::string(1, static_cast<char>(c))
                                    : fmt::format("\\x{:02x}", c);
    }
    return out;
}

bool format_supported(std::uint8_t f) { return f <= 10; }

// Formats 4, 5, 9, 10: the wave packet fields (Tables 11, 12, 16, 17).
void decode_wave(const std::uint8_t* w, LasPoint& p) {
    p.wave_index = w[0];
    p.wave_offset = get_u64(w + 1);
    p.wave_size = get_u32(w + 9);
    p.wave_location_ps = get_f32(w + 13);
    p.wave_dx = get_f32(w + 17);
    p.wave_dy = get_f32(w + 21);
    p.wave_dz = get_f32(w + 25);
}

LasPoint decode(const std::uint8_t* r, std::uint8_t f, const LasHeaderInfo& h) {
    LasPoint p{};
    p.raw_x = get_i32(r + 0);
    p.raw_y = get_i32(r + 4);
    p.raw_z = get_i32(r + 8);
    p.x = h.offset[0] + p.raw_x * h.scale[0];
    p.y = h.offset[1] + p.raw_y * h.scale[1];
    p.z = h.offset[2] + p.raw_z * h.scale[2];
    p.intensity = get_u16(r + 12);
    const std::uint8_t b = r[14];
    if (f < 6) {
        p.return_number = b & 0x07;
        p.number_of_returns = (b >> 3) & 0x07;
        p.scan_direction = (b >> 6) & 1;
        p.edge_of_flight_line = (b >> 7) & 1;
        p.classification = r[15] & 0x1F;
        p.scan_angle_deg = static_cast<std::int8_t>(r[16]);
        p.point_source_id = get_u16(r + 18);
        p.gps_time = (f == 0 || f == 2) ? 0.0 : get_f64(r + 20);
        const std::size_t rgb = f == 2 ? 20 : 28;
        if (f == 2 || f == 3 || f == 5) {
            p.red = get_u16(r + rgb);
            p.green = get_u16(r + rgb + 2);
            p.blue = get_u16(r + rgb + 4);
        }
    } else {
        p.return_number = b & 0x0F;
        p.number_of_returns = (b >> 4) & 0x0F;
        p.scanner_channel = (r[15] >> 4) & 0x03;
        p.scan_direction = (r[15] >> 6) & 1;
        p.edge_of_flight_line = (r[15] >> 7) & 1;
        p.classification = r[16];
        p.scan_angle_deg = static_cast<float>(get_i16(r + 18) * kScanAngleUnit_deg);
        p.point_source_id = get_u16(r + 20);
        p.gps_time = get_f64(r + 22);
        if (f == 7 || f == 8 || f == 10) {
            p.red = get_u16(r + 30);
            p.green = get_u16(r + 32);
            p.blue = get_u16(r + 34);
        }
    }
    if (const std::size_t w = wave_fields_at(f)) decode_wave(r + w, p);
    return p;
}

}  // namespace

namespace {

std::vector<std::uint8_t> slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("las reader '" + path + "': cannot open: " + std::strerror(errno));
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError("las reader '" + path + "': read error");
    return bytes;
}

}  // namespace

LasFile LasFile::read(const std::string& path) {
    const std::vector<std::uint8_t> bytes = slurp(path);
    const bool external = bytes.size() > kGlobalEncoding + 1 &&
                          (get_u16(bytes.data() + kGlobalEncoding) & kGlobalEncodingWaveExternal);
    if (!external) return from_bytes(bytes, nullptr);
    const std::string wdp_path = WdpFile::path_for(path);
    std::vector<std::uint8_t> wdp;
    try {
        wdp = slurp(wdp_path);
    } catch (const IoError&) {
        LasFile f = from_bytes(bytes, nullptr);
        f.problems_.push_back("waveform packets are external but '" + wdp_path +
                              "' cannot be read");
        return f;
    }
    return from_bytes(bytes, &wdp);
}

LasFile LasFile::from_bytes(const std::vector<std::uint8_t>& bytes) {
    return from_bytes(bytes, nullptr);
}

LasFile LasFile::from_bytes(const std::vector<std::uint8_t>& bytes,
                            const std::vector<std::uint8_t>* wdp) {
    LasFile f;
    f.parse(bytes);
    f.load_waves(bytes, wdp);
    f.check_waves();
    return f;
}

std::vector<std::string> LasFile::validate() const { return problems_; }

void LasFile::parse(const std::vector<std::uint8_t>& bytes) {
    auto problem = [this](std::string s) { problems_.push_back(std::move(s)); };
    const std::uint64_t n = bytes.size();
    file_size_ = n;
    const std::uint8_t* d = bytes.data();
    LasHeaderInfo& h = header_;

    // An empty file has no data() pointer, which memcpy must not get even for 0 bytes (fuzz_las).
    if (n > 0) std::memcpy(h.signature, d, std::min<std::uint64_t>(n, 4));
    if (n < 4 || std::memcmp(d, "LASF", 4) != 0) {
        problem(fmt::format("bad signature '{}' (expected 'LASF')",
                            printable(h.signature, std::min<std::uint64_t>(n, 4))));
    }
    if (n < kHeaderSize12) {
        problem(fmt::format("file is {} bytes, shorter than the smallest LAS header ({})", n,
                            kHeaderSize12));
        return;
    }

    h.file_source_id = get_u16(d + kFileSourceId);
    h.global_encoding = get_u16(d + kGlobalEncoding);
    h.version_major = d[kVersionMajor];
    h.version_minor = d[kVersionMinor];
    h.system_identifier = fixed_text(d + kSystemIdentifier, 32);
    h.generating_software = fixed_text(d + kGeneratingSoftware, 32);
    h.creation_day = get_u16(d + kCreationDay);
    h.creation_year = get_u16(d + kCreationYear);
    h.header_size = get_u16(d + kHeaderSize);
    h.offset_to_points = get_u32(d + kOffsetToPoints);
    h.vlr_count = get_u32(d + kVlrCount);
    h.point_format = d[kPointFormat];
    h.record_length = get_u16(d + kRecordLength);
    h.legacy_point_count = get_u32(d + kLegacyPointCount);
    for (int i = 0; i < 5; ++i) h.legacy_points_by_return[i] = get_u32(d + kLegacyByReturn + 4 * i);
    for (int a = 0; a < 3; ++a) {
        h.scale[a] = get_f64(d + kScale + 8 * a);
        h.offset[a] = get_f64(d + kOffset + 8 * a);
        h.max[a] = get_f64(d + kMaxX + 16 * a);
        h.min[a] = get_f64(d + kMaxX + 16 * a + 8);
    }

    const unsigned minor = h.version_minor;
    if (h.version_major != 1 || minor > 4) {
        problem(
            fmt::format("unsupported version {}.{} (expected 1.0 to 1.4)", h.version_major, minor));
    }
    const std::size_t expected_header =
        minor <= 2 ? kHeaderSize12 : (minor == 3 ? kHeaderSize13 : kHeaderSize14);
    if (h.header_size < expected_header) {
        problem(fmt::format("header size {} too small for LAS 1.{} (expected {})", h.header_size,
                            minor, expected_header));
    }
    if (h.header_size > n) {
        problem(fmt::format("header size {} beyond file size {}", h.header_size, n));
    }
    // The 1.4 fields exist only when the header really is a 1.4 one and is in the file.
    const bool v14 =
        h.version_major == 1 && minor >= 4 && h.header_size >= kHeaderSize14 && n >= kHeaderSize14;
    if (h.version_major == 1 && minor >= 3 && h.header_size >= kHeaderSize13 && n >= kHeaderSize13)
        h.start_of_waveform = get_u64(d + kWaveformStart);
    if (v14) {
        h.start_of_first_evlr = get_u64(d + kFirstEvlr);
        h.evlr_count = get_u32(d + kEvlrCount);
        h.point_count = get_u64(d + kPointCount);
        for (int i = 0; i < 15; ++i) h.points_by_return[i] = get_u64(d + kByReturn + 8 * i);
    } else {
        h.point_count = h.legacy_point_count;
        for (int i = 0; i < 5; ++i) h.points_by_return[i] = h.legacy_points_by_return[i];
    }

    for (int a = 0; a < 3; ++a) {
        if (!(h.scale[a] > 0.0) || !std::isfinite(h.scale[a])) {
            problem(fmt::format("scale {} is {}, must be > 0", kAxis[a], h.scale[a]));
        }
    }

    const std::uint8_t f = h.point_format;
    bool extra_bytes_vlr = false;
    if (h.offset_to_points < h.header_size) {
        problem(fmt::format("offset to points {} lies inside the {}-byte header",
                            h.offset_to_points, h.header_size));
    }
    if (h.offset_to_points > n) {
        problem(fmt::format("offset to points {} beyond file size {}", h.offset_to_points, n));
    }

    // VLRs live between the header and the point data; never walk past either end.
    const std::uint64_t vlr_end = std::min<std::uint64_t>(h.offset_to_points, n);
    std::uint64_t pos = h.header_size;
    for (std::uint32_t i = 0; i < h.vlr_count; ++i) {
        if (pos + kVlrHeaderSize > vlr_end) {
            problem(
                fmt::format("VLR {} of {} runs past the start of the point data", i, h.vlr_count));
            break;
        }
        const std::uint8_t* v = d + pos;
        const std::string user = fixed_text(v + 2, 16);
        const std::uint16_t id = get_u16(v + 18);
        const std::uint16_t len = get_u16(v + 20);
        if (pos + kVlrHeaderSize + len > vlr_end) {
            problem(
                fmt::format("VLR {} ('{}' {}) of {} bytes runs past the start of the point "
                            "data",
                            i, user, id, len));
            break;
        }
        if (user == "LASF_Projection" && id == kWktRecordId) {
            h.has_wkt_vlr = true;
            h.wkt = fixed_text(v + kVlrHeaderSize, len);
        }
        if (user == "LASF_Spec" && id == kExtraBytesRecordId) extra_bytes_vlr = true;
        read_vlr(v, user, id, len);
        pos += kVlrHeaderSize + len;
    }

    const bool wkt_bit = (h.global_encoding & kGlobalEncodingWkt) != 0;
    if (wkt_bit && !h.has_wkt_vlr && f < 6) {
        problem("global encoding WKT bit set but no WKT VLR (LASF_Projection 2112)");
    }
    if (v14 && f >= 6 && f <= 10 && !wkt_bit) {
        problem(fmt::format("point format {} requires the global encoding WKT bit", f));
    }

    bool record_ok = false;
    if (f >= kRecordLengths.size()) {
        problem(fmt::format("point format {} does not exist", f));
    } else if (h.record_length < kRecordLengths[f]) {
        problem(fmt::format("record length {} too short for point format {} (needs {})",
                            h.record_length, f, kRecordLengths[f]));
    } else {
        record_ok = true;
        if (h.record_length > kRecordLengths[f] && !extra_bytes_vlr) {
            problem(
                fmt::format("record length {} does not match point format {} ({} bytes) and "
                            "no Extra Bytes VLR describes the rest",
                            h.record_length, f, kRecordLengths[f]));
        }
        if (!format_supported(f)) {
            problem(fmt::format("point format {} not supported by this reader", f));
            record_ok = false;
        }
    }

    // Counts against the bytes actually present.
    std::uint64_t data_end = n;
    if (v14 && h.evlr_count > 0 && h.start_of_first_evlr >= h.offset_to_points) {
        data_end = std::min<std::uint64_t>(h.start_of_first_evlr, n);
    }
    if (h.record_length > 0 && h.offset_to_points <= data_end) {
        const std::uint64_t room = data_end - h.offset_to_points;
        records_in_file_ = room / h.record_length;
        if (h.point_count > records_in_file_) {
            problem(
                fmt::format("header says {} points but the file holds only {} whole records "
                            "(truncated?)",
                            h.point_count, records_in_file_));
        } else if (h.point_count < records_in_file_) {
            problem(fmt::format("file holds {} whole records but the header says {} points",
                                records_in_file_, h.point_count));
        }
        if (room % h.record_length != 0) {
            problem(fmt::format("{} bytes after the last whole record (a cut record?)",
                                room % h.record_length));
        }
    }
    if (v14) {
        if (f < 6) {
            // LAS 1.4 §2.4: formats 0–5 keep the legacy fields in step when the count fits.
            if (h.point_count <= std::numeric_limits<std::uint32_t>::max()) {
                if (h.legacy_point_count != h.point_count) {
                    problem(fmt::format("legacy point count {} differs from point count {}",
                                        h.legacy_point_count, h.point_count));
                }
                for (int i = 0; i < 5; ++i) {
                    if (h.legacy_points_by_return[i] != h.points_by_return[i]) {
                        problem(fmt::format("legacy count of return {} is {}, 64-bit count is {}",
                                            i + 1, h.legacy_points_by_return[i],
                                            h.points_by_return[i]));
                    }
                }
            }
        } else {
            if (h.legacy_point_count != 0) {
                problem(fmt::format("legacy point count must be 0 for point format {}, is {}", f,
                                    h.legacy_point_count));
            }
            for (int i = 0; i < 5; ++i) {
                if (h.legacy_points_by_return[i] != 0) {
                    problem(
                        fmt::format("legacy count of return {} must be 0 for point format "
                                    "{}, is {}",
                                    i + 1, f, h.legacy_points_by_return[i]));
                }
            }
        }
    }
    std::uint64_t by_return_sum = 0;
    for (std::uint64_t c : h.points_by_return) by_return_sum += c;
    if (by_return_sum != h.point_count) {
        problem(fmt::format("counts by return sum to {}, point count is {}", by_return_sum,
                            h.point_count));
    }

    if (!record_ok || h.offset_to_points > n) return;
    const std::uint64_t count = std::min(h.point_count, records_in_file_);
    points_.reserve(count);
    for (std::uint64_t k = 0; k < count; ++k) {
        points_.push_back(decode(d + h.offset_to_points + k * h.record_length, f, h));
    }

    // The header's statistics against the points themselves.
    std::array<std::uint64_t, 15> seen{};
    std::uint64_t bad_return = 0;
    for (const LasPoint& p : points_) {
        if (p.return_number >= 1 && p.return_number <= 15) {
            ++seen[p.return_number - 1u];
        } else {
            ++bad_return;
        }
    }
    if (bad_return > 0) problem(fmt::format("{} points have return number 0", bad_return));
    if (count == h.point_count) {
        for (int i = 0; i < 15; ++i) {
            if (seen[i] != h.points_by_return[i]) {
                problem(fmt::format("header counts {} points of return {}, the file has {}",
                                    h.points_by_return[i], i + 1, seen[i]));
            }
        }
    }
    if (points_.empty()) return;
    std::array<double, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -std::numeric_limits<double>::infinity();
    }
    for (const LasPoint& p : points_) {
        const double v[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], v[a]);
            hi[a] = std::max(hi[a], v[a]);
        }
    }
    for (int a = 0; a < 3; ++a) {
        const double tol = std::abs(h.scale[a]) / 2;
        if (!(std::abs(h.min[a] - lo[a]) <= tol)) {
            problem(fmt::format("min {} in header is {:.6f} but the points reach {:.6f}", kAxis[a],
                                h.min[a], lo[a]));
        }
        if (!(std::abs(h.max[a] - hi[a]) <= tol)) {
            problem(fmt::format("max {} in header is {:.6f} but the points reach {:.6f}", kAxis[a],
                                h.max[a], hi[a]));
        }
    }
}

}  // namespace mirage::las
