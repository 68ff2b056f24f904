// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/metadata.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "json_lite.hpp"
#include "mirage/core/error.hpp"

namespace mirage::ouster {
namespace {

std::string num(double v) {
    if (!std::isfinite(v)) return "0";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round trip
    return std::string(buf, r.ptr);
}

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out.push_back('\\');
        out.push_back(c);
    }
    return out + "\"";
}

template <class Seq>
std::string list(const Seq& values) {
    std::string out = "[";
    bool first = true;
    for (const auto& v : values) {
        out += (first ? "" : ", ") + num(double(v));
        first = false;
    }
    return out + "]";
}

// Writes one object, members in insertion order, nested with 2-space indents.
class Obj {
  public:
    Obj& add(const std::string& key, const std::string& raw) {
        members_.emplace_back(key, raw);
        return *this;
    }
    Obj& str(const std::string& key, const std::string& v) { return add(key, quoted(v)); }
    Obj& number(const std::string& key, double v) { return add(key, num(v)); }
    std::string render(int indent = 0) const {
        const std::string pad(std::size_t(indent + 2), ' ');
        std::string out = "{\n";
        for (std::size_t i = 0; i < members_.size(); ++i) {
            out += pad + quoted(members_[i].first) + ": " + members_[i].second;
            out += i + 1 < members_.size() ? ",\n" : "\n";
        }
        return out + std::string(std::size_t(indent), ' ') + "}";
    }

  private:
    std::vector<std::pair<std::string, std::string>> members_;
};

std::array<double, 16> beam_to_lidar(const Descriptor& d) {
    return {1, 0, 0, d.beam_origin_mm, 0, 1, 0, 0, 0, 0, 1, d.beam_z_mm, 0, 0, 0, 1};
}

std::string window(const Descriptor& d) {
    return "[0, " + std::to_string(d.mode.columns - 1) + "]";
}

Obj data_format(const Descriptor& d) {
    Obj f;
    f.add("pixels_per_column", std::to_string(d.beams))
        .add("columns_per_packet", std::to_string(d.columns_per_packet))
        .add("columns_per_frame", std::to_string(d.mode.columns))
        .add("pixel_shift_by_row", list(d.pixel_shift_by_row()))
        .add("column_window", window(d))
        .str("udp_profile_lidar", to_string(d.profile))
        .str("udp_profile_imu", "LEGACY");
    return f;
}

}  // namespace

std::string metadata_json(const Descriptor& d, const MetadataOptions& o) {
    const std::string sn = std::to_string(d.serial);
    const std::string image = "ousteros-image-prod-mirage-" + d.firmware;
    if (o.shape == MetadataShape::Fw2Flat) {
        Obj root;
        root.str("base_pn", "")
            .str("base_sn", "")
            .add("beam_altitude_angles", list(d.altitude_deg))
            .add("beam_azimuth_angles", list(d.azimuth_deg))
            .str("build_date", "2024-01-01T00:00:00Z")
            .str("build_rev", d.firmware)
            .str("client_version", "mirage")
            .add("data_format", data_format(d).render(2))
            .str("hostname", "")
            .str("image_rev", image)
            .add("imu_to_sensor_transform", list(d.imu_to_sensor))
            .number("initialization_id", d.init_id)
            .number("json_calibration_version", 4)
            .str("lidar_mode", to_string(d.mode))
            .number("lidar_origin_to_beam_origin_mm", d.beam_origin_mm)
            .add("lidar_to_sensor_transform", list(d.lidar_to_sensor))
            .str("prod_line", d.prod_line())
            .str("prod_pn", d.part_number)
            .str("prod_sn", sn)
            .str("proto_rev", "")
            .str("status", "RUNNING")
            .number("udp_port_imu", d.udp_port_imu)
            .number("udp_port_lidar", d.udp_port_lidar);
        return root.render() + "\n";
    }
    Obj sensor_info;
    sensor_info.str("prod_line", d.prod_line())
        .str("prod_pn", d.part_number)
        .str("prod_sn", sn)
        .str("build_rev", d.firmware)
        .str("build_date", "2024-01-01T00:00:00Z")
        .str("image_rev", image)
        .number("initialization_id", d.init_id)
        .str("status", "RUNNING")
        .str("proto_rev", "")
        .str("base_pn", "")
        .str("base_sn", "");
    Obj beams;
    beams.add("beam_altitude_angles", list(d.altitude_deg))
        .add("beam_azimuth_angles", list(d.azimuth_deg))
        .number("lidar_origin_to_beam_origin_mm", d.beam_origin_mm)
        .add("beam_to_lidar_transform", list(beam_to_lidar(d)));
    Obj format = data_format(d);
    format.number("fps", d.mode.hz);
    Obj config;
    config.str("lidar_mode", to_string(d.mode))
        .str("udp_dest", o.udp_dest)
        .number("udp_port_lidar", d.udp_port_lidar)
        .number("udp_port_imu", d.udp_port_imu)
        .str("udp_profile_lidar", to_string(d.profile))
        .str("udp_profile_imu", "LEGACY")
        .number("columns_per_packet", d.columns_per_packet)
        .add("azimuth_window", "[0, 360000]")
        .str("timestamp_mode", to_string(o.timestamp_mode))
        .str("operating_mode", "NORMAL")
        .str("multipurpose_io_mode", "OFF")
        .str("sync_pulse_in_polarity", "ACTIVE_HIGH")
        .str("nmea_in_polarity", "ACTIVE_HIGH")
        .str("nmea_baud_rate", "BAUD_9600")
        .number("signal_multiplier", 1)
        .str("phase_lock_enable", "false");
    Obj imu, lidar, refl, cal;
    imu.add("imu_to_sensor_transform", list(d.imu_to_sensor));
    lidar.add("lidar_to_sensor_transform", list(d.lidar_to_sensor));
    refl.add("valid", "false").str("timestamp", "");
    cal.add("reflectivity", refl.render(4));
    Obj root;
    root.add("sensor_info", sensor_info.render(2))
        .add("beam_intrinsics", beams.render(2))
        .add("lidar_data_format", format.render(2))
        .add("config_params", config.render(2))
        .add("imu_intrinsics", imu.render(2))
        .add("lidar_intrinsics", lidar.render(2))
        .add("calibration_status", cal.render(2));
    return root.render() + "\n";
}

namespace {

class Reader {
  public:
    explicit Reader(std::string source) : source_(std::move(source)) {}
    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw ConfigError("ouster metadata '" + source_ + "': " + key + ": " + what);
    }
    const json::Value* get(const json::Value* obj, const char* key) const {
        return obj && obj->kind == json::Value::Kind::Object ? obj->find(key) : nullptr;
    }
    double number(const json::Value* v, const std::string& key) const {
        if (!v || v->kind != json::Value::Kind::Number) fail(key, "expected a number");
        return v->number;
    }
    std::string text(const json::Value* v, const std::string& key) const {
        if (!v || v->kind != json::Value::Kind::String) fail(key, "expected a string");
        return v->text;
    }
    std::vector<double> numbers(const json::Value* v, const std::string& key) const {
        if (!v || v->kind != json::Value::Kind::Array) fail(key, "expected an array of numbers");
        std::vector<double> out;
        for (const auto& x : v->items) out.push_back(number(&x, key));
        return out;
    }
    std::array<double, 16> matrix(const json::Value* v, const std::string& key) const {
        const auto n = numbers(v, key);
        if (n.size() != 16) fail(key, "expected 16 numbers");
        std::array<double, 16> m{};
        std::copy(n.begin(), n.end(), m.begin());
        return m;
    }

  private:
    std::string source_;
};

}  // namespace

Descriptor descriptor_from_metadata(const std::string& text, const std::string& source) {
    const Reader rd(source);
    json::Value root;
    try {
        root = json::parse(text);
    } catch (const std::exception& e) {
        rd.fail("(document)", e.what());
    }
    if (root.kind != json::Value::Kind::Object) rd.fail("(document)", "expected an object");
    const bool nested = root.find("sensor_info") != nullptr;
    const json::Value* info = nested ? root.find("sensor_info") : &root;
    const json::Value* beams = nested ? root.find("beam_intrinsics") : &root;
    const json::Value* format = nested ? root.find("lidar_data_format") : root.find("data_format");
    const json::Value* config = nested ? root.find("config_params") : &root;

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
    const json::Value* lidar_t =
        nested ? rd.get(root.find("lidar_intrinsics"), "lidar_to_sensor_transform")
               : root.find("lidar_to_sensor_transform");
    if (lidar_t) d.lidar_to_sensor = rd.matrix(lidar_t, "lidar_to_sensor_transform");
    const json::Value* imu_t = nested
                                   ? rd.get(root.find("imu_intrinsics"), "imu_to_sensor_transform")
                                   : root.find("imu_to_sensor_transform");
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
        const std::string s =
            v->kind == json::Value::Kind::String ? v->text : num(rd.number(v, "prod_sn"));
        std::uint64_t sn = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), sn);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) rd.fail("prod_sn", "not a number");
        d.serial = sn;
    }
    if (const auto* v = rd.get(info, "initialization_id"))
        d.init_id = static_cast<std::uint32_t>(rd.number(v, "initialization_id"));
    if (const auto* v = rd.get(info, "build_rev")) d.firmware = rd.text(v, "build_rev");
    if (const auto* v = rd.get(info, "prod_pn")) d.part_number = rd.text(v, "prod_pn");
    // FW 2.x streams carry the footer placeholder; FW 3.x a CRC.
    d.footer = d.firmware.rfind("v2.", 0) == 0 || d.firmware.rfind("v1.", 0) == 0
                   ? FooterKind::Fw2Placeholder
                   : FooterKind::Crc64;
    if (const auto* v = rd.get(config, "udp_port_lidar"))
        d.udp_port_lidar = static_cast<std::uint16_t>(rd.number(v, "udp_port_lidar"));
    if (const auto* v = rd.get(config, "udp_port_imu"))
        d.udp_port_imu = static_cast<std::uint16_t>(rd.number(v, "udp_port_imu"));
    return d;
}

Descriptor load_metadata(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("ouster metadata '" + path + "': cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    return descriptor_from_metadata(ss.str(), path);
}

}  // namespace mirage::ouster
