// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/metadata.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::ouster {
namespace {

// Written documents keep insertion order (the order the SDK and the sensor use); reading does not
// care about order.
using OJson = nlohmann::ordered_json;
using Json = nlohmann::json;

// Integral values as JSON integers ("1", not "1.0"), as the sensor writes them; everything else as
// a double, which nlohmann dumps as the shortest round-trip decimal.
OJson num(double v) {
    if (!std::isfinite(v)) return 0;
    constexpr double kExactInt = 9007199254740992.0;  // 2^53: every integer below is exact
    if (v == std::trunc(v) && std::abs(v) < kExactInt && !(v == 0 && std::signbit(v)))
        return static_cast<std::int64_t>(v);
    return v;
}

template <class Seq>
OJson list(const Seq& values) {
    OJson out = OJson::array();
    for (const auto& v : values) out.push_back(num(double(v)));
    return out;
}

std::array<double, 16> beam_to_lidar(const Descriptor& d) {
    return {1, 0, 0, d.beam_origin_mm, 0, 1, 0, 0, 0, 0, 1, d.beam_z_mm, 0, 0, 0, 1};
}

OJson window(const Descriptor& d) { return OJson::array({0, int(d.mode.columns) - 1}); }

OJson data_format(const Descriptor& d) {
    return {
        {"pixels_per_column", d.beams},        {"columns_per_packet", d.columns_per_packet},
        {"columns_per_frame", d.mode.columns}, {"pixel_shift_by_row", list(d.pixel_shift_by_row())},
        {"column_window", window(d)},          {"udp_profile_lidar", to_string(d.profile)},
        {"udp_profile_imu", "LEGACY"}};
}

// Strings come from user configuration (firmware, udp_dest): replace invalid UTF-8 rather than
// let dump() throw.
std::string render(const OJson& root) {
    return root.dump(2, ' ', false, OJson::error_handler_t::replace) + "\n";
}

}  // namespace

std::string metadata_json(const Descriptor& d, const MetadataOptions& o) {
    const std::string sn = std::to_string(d.serial);
    const std::string image = "ousteros-image-prod-mirage-" + d.firmware;
    if (o.shape == MetadataShape::Fw2Flat) {
        return render({{"base_pn", ""},
                       {"base_sn", ""},
                       {"beam_altitude_angles", list(d.altitude_deg)},
                       {"beam_azimuth_angles", list(d.azimuth_deg)},
                       {"build_date", "2024-01-01T00:00:00Z"},
                       {"build_rev", d.firmware},
                       {"client_version", "mirage"},
                       {"data_format", data_format(d)},
                       {"hostname", ""},
                       {"image_rev", image},
                       {"imu_to_sensor_transform", list(d.imu_to_sensor)},
                       {"initialization_id", d.init_id},
                       {"json_calibration_version", 4},
                       {"lidar_mode", to_string(d.mode)},
                       {"lidar_origin_to_beam_origin_mm", num(d.beam_origin_mm)},
                       {"lidar_to_sensor_transform", list(d.lidar_to_sensor)},
                       {"prod_line", d.prod_line()},
                       {"prod_pn", d.part_number},
                       {"prod_sn", sn},
                       {"proto_rev", ""},
                       {"status", "RUNNING"},
                       {"udp_port_imu", d.udp_port_imu},
                       {"udp_port_lidar", d.udp_port_lidar}});
    }
    OJson format = data_format(d);
    format["fps"] = int(d.mode.hz);
    const OJson root = {
        {"sensor_info",
         {{"prod_line", d.prod_line()},
          {"prod_pn", d.part_number},
          {"prod_sn", sn},
          {"build_rev", d.firmware},
          {"build_date", "2024-01-01T00:00:00Z"},
          {"image_rev", image},
          {"initialization_id", d.init_id},
          {"status", "RUNNING"},
          {"proto_rev", ""},
          {"base_pn", ""},
          {"base_sn", ""}}},
        {"beam_intrinsics",
         {{"beam_altitude_angles", list(d.altitude_deg)},
          {"beam_azimuth_angles", list(d.azimuth_deg)},
          {"lidar_origin_to_beam_origin_mm", num(d.beam_origin_mm)},
          {"beam_to_lidar_transform", list(beam_to_lidar(d))}}},
        {"lidar_data_format", format},
        {"config_params",
         {{"lidar_mode", to_string(d.mode)},
          {"udp_dest", o.udp_dest},
          {"udp_port_lidar", d.udp_port_lidar},
          {"udp_port_imu", d.udp_port_imu},
          {"udp_profile_lidar", to_string(d.profile)},
          {"udp_profile_imu", "LEGACY"},
          {"columns_per_packet", d.columns_per_packet},
          {"azimuth_window", OJson::array({0, 360000})},
          {"timestamp_mode", to_string(o.timestamp_mode)},
          {"operating_mode", "NORMAL"},
          {"multipurpose_io_mode", "OFF"},
          {"sync_pulse_in_polarity", "ACTIVE_HIGH"},
          {"nmea_in_polarity", "ACTIVE_HIGH"},
          {"nmea_baud_rate", "BAUD_9600"},
          {"signal_multiplier", 1},
          {"phase_lock_enable", "false"}}},
        {"imu_intrinsics", {{"imu_to_sensor_transform", list(d.imu_to_sensor)}}},
        {"lidar_intrinsics", {{"lidar_to_sensor_transform", list(d.lidar_to_sensor)}}},
        {"calibration_status", {{"reflectivity", {{"valid", false}, {"timestamp", ""}}}}}};
    return render(root);
}

namespace {

class Reader {
  public:
    explicit Reader(std::string source) : source_(std::move(source)) {}
    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw ConfigError("ouster metadata '" + source_ + "': " + key + ": " + what);
    }
    const Json* get(const Json* obj, const char* key) const {
        if (!obj || !obj->is_object()) return nullptr;
        const auto it = obj->find(key);
        return it == obj->end() ? nullptr : &*it;
    }
    double number(const Json* v, const std::string& key) const {
        if (!v || !v->is_number()) fail(key, "expected a number");
        return v->get<double>();
    }
    // A whole number in [0, max]: converting anything else to an unsigned type is undefined.
    std::uint64_t whole(const Json* v, const std::string& key, std::uint64_t max) const {
        const double x = number(v, key);
        if (!(x >= 0.0 && x <= double(max)) || x != std::floor(x))
            fail(key, "expected a whole number from 0 to " + std::to_string(max));
        return static_cast<std::uint64_t>(x);
    }
    std::string text(const Json* v, const std::string& key) const {
        if (!v || !v->is_string()) fail(key, "expected a string");
        return v->get<std::string>();
    }
    std::vector<double> numbers(const Json* v, const std::string& key) const {
        if (!v || !v->is_array()) fail(key, "expected an array of numbers");
        std::vector<double> out;
        out.reserve(v->size());
        for (const auto& x : *v) out.push_back(number(&x, key));
        return out;
    }
    std::array<double, 16> matrix(const Json* v, const std::string& key) const {
        const auto n = numbers(v, key);
        if (n.size() != 16) fail(key, "expected 16 numbers");
        std::array<double, 16> m{};
        std::copy(n.begin(), n.end(), m.begin());
        return m;
    }

  private:
    std::string source_;
};

// nlohmann's what() is "[json.exception.parse_error.101] parse error at line 1, column 5: ...";
// keep "line 1, column 5: ...".
std::string problem(const Json::exception& e) {
    std::string what = e.what();
    if (const auto p = what.find("] "); what.rfind("[json.exception.", 0) == 0 && p != what.npos)
        what.erase(0, p + 2);
    for (const std::string prefix : {"parse error at ", "parse error: "})
        if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
    return what;
}

Descriptor read_descriptor(const Json& root, const Reader& rd) {
    if (!root.is_object()) rd.fail("(document)", "expected an object");
    const Json* info = rd.get(&root, "sensor_info");
    const bool nested = info != nullptr;
    if (!nested) info = &root;
    const Json* beams = nested ? rd.get(&root, "beam_intrinsics") : &root;
    const Json* format = rd.get(&root, nested ? "lidar_data_format" : "data_format");
    const Json* config = nested ? rd.get(&root, "config_params") : &root;

    Descriptor d;
    const std::string prefix = nested ? "beam_intrinsics." : "";
    d.altitude_deg =
        rd.numbers(rd.get(beams, "beam_altitude_angles"), prefix + "beam_altitude_angles");
    d.azimuth_deg =
        rd.numbers(rd.get(beams, "beam_azimuth_angles"), prefix + "beam_azimuth_angles");
    const std::size_t H = d.altitude_deg.size();
    if (H != 32 && H != 64 && H != 128 && H != 16)
        rd.fail(prefix + "beam_altitude_angles", std::to_string(H) + " beams");
    if (d.azimuth_deg.size() != H)
        rd.fail(prefix + "beam_azimuth_angles", "expected " + std::to_string(H) + " angles");
    d.beams = static_cast<std::uint16_t>(H);
    const std::string mode_key = nested ? "config_params.lidar_mode" : "lidar_mode";
    try {
        d.mode = parse_lidar_mode(rd.text(rd.get(config, "lidar_mode"), mode_key));
    } catch (const ConfigError& e) {
        if (std::string(e.what()).rfind("ouster metadata", 0) == 0) throw;
        rd.fail(mode_key, e.what());
    }

    // Product line from "OS-1-64" / "OS-2-128"; gen-1 files have none (OS-1).
    d.line = ProductLine::OS1;
    if (const auto* pl = rd.get(info, "prod_line")) {
        const std::string s = rd.text(pl, "prod_line");
        if (s.rfind("OS-0", 0) == 0 || s.rfind("OS0", 0) == 0) d.line = ProductLine::OS0;
        if (s.rfind("OS-2", 0) == 0 || s.rfind("OS2", 0) == 0) d.line = ProductLine::OS2;
    }
    d.beam_origin_mm = d.line == ProductLine::OS0   ? 27.67
                       : d.line == ProductLine::OS2 ? 13.762
                                                    : 15.806;
    if (const auto* v = rd.get(beams, "lidar_origin_to_beam_origin_mm"))
        d.beam_origin_mm = rd.number(v, prefix + "lidar_origin_to_beam_origin_mm");
    if (const auto* v = rd.get(beams, "beam_to_lidar_transform")) {
        const auto m = rd.matrix(v, prefix + "beam_to_lidar_transform");
        d.beam_origin_mm = m[3];
        d.beam_z_mm = m[11];
    }
    const Json* lidar_t =
        rd.get(nested ? rd.get(&root, "lidar_intrinsics") : &root, "lidar_to_sensor_transform");
    if (lidar_t) d.lidar_to_sensor = rd.matrix(lidar_t, "lidar_to_sensor_transform");
    const Json* imu_t =
        rd.get(nested ? rd.get(&root, "imu_intrinsics") : &root, "imu_to_sensor_transform");
    if (imu_t) d.imu_to_sensor = rd.matrix(imu_t, "imu_to_sensor_transform");

    d.profile = Profile::Legacy;
    d.columns_per_packet = 16;
    if (format) {
        const std::string fk = nested ? "lidar_data_format." : "data_format.";
        if (const auto* v = rd.get(format, "udp_profile_lidar")) {
            try {
                d.profile = parse_profile(rd.text(v, fk + "udp_profile_lidar"));
            } catch (const ConfigError& e) {
                if (std::string(e.what()).rfind("ouster metadata", 0) == 0) throw;
                rd.fail(fk + "udp_profile_lidar", e.what());
            }
        }
        if (const auto* v = rd.get(format, "columns_per_packet")) {
            const double c = rd.number(v, fk + "columns_per_packet");
            if (!(c >= 1 && c <= d.mode.columns) || std::fmod(d.mode.columns, c) != 0)
                rd.fail(fk + "columns_per_packet", "does not divide the frame");
            d.columns_per_packet = static_cast<std::uint16_t>(c);
        }
        if (const auto* v = rd.get(format, "pixels_per_column"))
            if (rd.number(v, fk + "pixels_per_column") != double(H))
                rd.fail(fk + "pixels_per_column", "differs from the beam count");
    }
    d.serial = 0;
    d.init_id = 0;
    if (const auto* v = rd.get(info, "prod_sn")) {
        std::uint64_t sn = 0;
        if (v->is_number_unsigned()) {
            sn = v->get<std::uint64_t>();
        } else {
            // A number-typed serial (negative or fractional here) goes through its decimal form.
            const std::string s =
                v->is_string() ? v->get<std::string>() : OJson(num(rd.number(v, "prod_sn"))).dump();
            const auto r = std::from_chars(s.data(), s.data() + s.size(), sn);
            if (r.ec != std::errc() || r.ptr != s.data() + s.size())
                rd.fail("prod_sn", "not a number");
        }
        d.serial = sn;
    }
    if (const auto* v = rd.get(info, "initialization_id"))
        d.init_id = static_cast<std::uint32_t>(rd.whole(v, "initialization_id", 0xffffffffu));
    if (const auto* v = rd.get(info, "build_rev")) d.firmware = rd.text(v, "build_rev");
    if (const auto* v = rd.get(info, "prod_pn")) d.part_number = rd.text(v, "prod_pn");
    // FW 2.x streams carry the footer placeholder; FW 3.x a CRC.
    d.footer = d.firmware.rfind("v2.", 0) == 0 || d.firmware.rfind("v1.", 0) == 0
                   ? FooterKind::Fw2Placeholder
                   : FooterKind::Crc64;
    if (const auto* v = rd.get(config, "udp_port_lidar"))
        d.udp_port_lidar = static_cast<std::uint16_t>(rd.whole(v, "udp_port_lidar", 65535));
    if (const auto* v = rd.get(config, "udp_port_imu"))
        d.udp_port_imu = static_cast<std::uint16_t>(rd.whole(v, "udp_port_imu", 65535));
    return d;
}

}  // namespace

Descriptor descriptor_from_metadata(const std::string& text, const std::string& source) {
    const Reader rd(source);
    Json root;
    try {
        root = Json::parse(text);
    } catch (const Json::exception& e) {
        rd.fail("(document)", problem(e));
    }
    try {
        return read_descriptor(root, rd);
    } catch (const Json::exception& e) {  // the typed reads above should make this unreachable
        rd.fail("(document)", problem(e));
    }
}

Descriptor load_metadata(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("ouster metadata '" + path + "': cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    return descriptor_from_metadata(ss.str(), path);
}

}  // namespace mirage::ouster
