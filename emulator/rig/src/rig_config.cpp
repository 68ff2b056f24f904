// SPDX-License-Identifier: Apache-2.0
// Rig files (docs/rig.md §1): every key checked against a fixed list, every value against its
// range, then the rig as a whole (unique names, destinations and source ports).
#include "mirage/rig/rig_config.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "mirage/scene/yaml_reader.hpp"

namespace mirage::rig {
namespace {

namespace fs = std::filesystem;

class RigReader : private scene::YamlReader {
  public:
    explicit RigReader(const std::string& file)
        : YamlReader("rig '" + file + "'"), dir_(fs::path(file).parent_path()) {}

    RigConfig run(const std::string& file, const std::string* text) {
        const YAML::Node root = load(file, text);
        require_map(root, "");
        check_keys(root, "", {"scene", "navigation", "start", "duration", "threads", "sensors"});
        RigConfig c;
        c.file = file;
        if (!root["scene"]) fail("scene", "missing (demo or a scene file)", root);
        const std::string scene = string(root["scene"], "scene");
        c.scene = scene == "demo" ? scene : file_path(scene);
        navigation(root["navigation"], c);
        if (root["start"]) c.start = string(root["start"], "start");
        if (root["duration"]) {
            (void)positive(root["duration"], "duration");
            c.duration = root["duration"].Scalar();  // kept as text: exact decimal seconds
        }
        if (root["threads"])
            c.threads = static_cast<int>(integer(root["threads"], "threads", 1, 64));
        sensors(root["sensors"], root, c);
        return c;
    }

  private:
    // Relative file names are the rig file's.
    std::string file_path(const std::string& v) const {
        return fs::path(v).is_absolute() ? v : (dir_ / v).string();
    }

    void navigation(const YAML::Node& n, RigConfig& c) const {
        const std::string p = "navigation";
        if (!n) fail(p, "missing (navigation: {trajectory: …} or {nav: <URI>})", n);
        require_map(n, p);
        check_keys(n, p,
                   {"trajectory", "nav", "origin", "max_extrapolation_ms", "first_nav_timeout"});
        if (!n["trajectory"] == !n["nav"])
            fail(p, "give one of trajectory (a path) or nav (a live source's URI)", n);
        if (n["trajectory"]) {
            for (const char* k : {"origin", "max_extrapolation_ms", "first_nav_timeout"})
                if (n[k]) fail(sub(p, k), "applies to nav only", n[k]);
            const std::string t = string(n["trajectory"], sub(p, "trajectory"));
            c.trajectory = t.starts_with("demo-") || t.starts_with("static:") ? t : file_path(t);
            return;
        }
        c.nav = string(n["nav"], sub(p, "nav"));
        if (n["origin"]) {
            c.nav_origin = numbers(n["origin"], sub(p, "origin"), 3);
            if (std::abs(c.nav_origin[0]) > 90 || std::abs(c.nav_origin[1]) > 180)
                fail(sub(p, "origin"), "latitude within ±90°, longitude within ±180°", n["origin"]);
        }
        if (n["max_extrapolation_ms"])
            c.max_extrapolation_ms =
                number_in(n["max_extrapolation_ms"], sub(p, "max_extrapolation_ms"), 0, 10'000);
        if (n["first_nav_timeout"])
            c.first_nav_timeout_s =
                number_in(n["first_nav_timeout"], sub(p, "first_nav_timeout"), 0.1, 3600);
    }

    void sensors(const YAML::Node& n, const YAML::Node& root, RigConfig& c) const {
        if (!n) fail("sensors", "missing (a rig needs at least one sensor)", root);
        if (!n.IsSequence() || n.size() == 0 || n.size() > 32)
            fail("sensors", "expected a list of 1 to 32 sensors", n);
        for (std::size_t i = 0; i < n.size(); ++i)
            c.sensors.push_back(sensor(n[i], item("sensors", i)));
        check_unique(n, c);
    }

    SensorEntry sensor(const YAML::Node& n, const std::string& path) const {
        require_map(n, path);
        check_keys(n, path,
                   {"name", "sensor", "mount", "return_mode", "rpm", "profile", "to", "source_port",
                    "ports", "pcap"});
        SensorEntry s;
        s.line = n.Mark().line + 1;
        if (!n["name"]) fail(sub(path, "name"), "missing", n);
        s.name = string(n["name"], sub(path, "name"));
        for (char ch : s.name)
            if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_')
                fail(sub(path, "name"), "letters, digits, '-' and '_' only", n["name"]);
        if (!n["sensor"]) fail(sub(path, "sensor"), "missing (a preset or a sensor file)", n);
        const std::string sensor = string(n["sensor"], sub(path, "sensor"));
        const bool file = sensor.ends_with(".yaml") || sensor.find('/') != std::string::npos;
        s.sensor = file ? file_path(sensor) : sensor;  // else a preset
        if (n["mount"]) mount(n["mount"], sub(path, "mount"), s);
        if (n["return_mode"]) {
            s.return_mode = string(n["return_mode"], sub(path, "return_mode"));
            if (s.return_mode != "strongest" && s.return_mode != "last" && s.return_mode != "dual")
                fail(sub(path, "return_mode"), "expected strongest, last or dual",
                     n["return_mode"]);
        }
        if (n["rpm"]) s.rpm = number_in(n["rpm"], sub(path, "rpm"), 60, 3000);
        if (n["profile"]) s.profile = string(n["profile"], sub(path, "profile"));
        if (n["to"]) s.to = string(n["to"], sub(path, "to"));
        if (n["source_port"]) s.source_port = port(n["source_port"], sub(path, "source_port"));
        if (n["ports"]) ports(n["ports"], sub(path, "ports"), s.ports);
        if (n["pcap"]) s.pcap = file_path(string(n["pcap"], sub(path, "pcap")));
        if (s.to.empty() && s.pcap.empty())
            fail(path, "sensor '" + s.name + "' has nowhere to go: give `to` and/or `pcap`", n);
        if (!s.to.empty() && s.ports.data == 0)
            fail(sub(path, "ports.data"), "missing (each sensor of a rig names its data port)", n);
        return s;
    }

    void mount(const YAML::Node& n, const std::string& path, SensorEntry& s) const {
        require_map(n, path);
        check_keys(n, path, {"lever_arm", "boresight"});
        const auto three = [&](const char* key, std::array<double, 3>& out, double limit) {
            if (!n[key]) return;
            const auto v = numbers(n[key], sub(path, key), 3);
            for (std::size_t a = 0; a < 3; ++a) {
                if (std::abs(v[a]) > limit)
                    fail(item(sub(path, key), a), "must be within ±" + std::to_string(int(limit)),
                         n[key][a]);
                out[a] = v[a];
            }
        };
        three("lever_arm", s.lever_arm, 100);
        three("boresight", s.boresight, 360);
    }

    std::uint16_t port(const YAML::Node& n, const std::string& path) const {
        return static_cast<std::uint16_t>(integer(n, path, 0, 65535));
    }

    void ports(const YAML::Node& n, const std::string& path, Ports& p) const {
        require_map(n, path);
        check_keys(n, path, {"data", "position", "imu"});
        if (n["data"])
            p.data = static_cast<std::uint16_t>(integer(n["data"], sub(path, "data"), 1, 65535));
        if (n["position"]) p.position = port(n["position"], sub(path, "position"));
        if (n["imu"]) p.imu = port(n["imu"], sub(path, "imu"));
    }

    // The node at a dotted key path under `n` (for the line of a message).
    static YAML::Node at(const YAML::Node& n, const std::string& key) {
        const auto dot = key.find('.');
        if (dot == std::string::npos) return n[key];
        return at(n[key.substr(0, dot)], key.substr(dot + 1));
    }

    // Names, destination host:port of every stream, and source ports: each claimed once.
    void check_unique(const YAML::Node& n, const RigConfig& c) const {
        std::map<std::string, std::size_t> names;
        std::map<std::string, std::string> claims;
        for (std::size_t i = 0; i < c.sensors.size(); ++i) {
            const SensorEntry& s = c.sensors[i];
            const std::string path = item("sensors", i);
            if (!names.emplace(s.name, i).second)
                fail(sub(path, "name"),
                     "'" + s.name + "' is also sensors[" + std::to_string(names[s.name]) + "]",
                     n[i]["name"]);
            const auto claim = [&](const std::string& what, const std::string& key) {
                const auto [it, fresh] = claims.emplace(what, s.name);
                if (!fresh)
                    fail(sub(path, key), what + " is also claimed by sensor '" + it->second + "'",
                         at(n[i], key));
            };
            if (!s.to.empty())
                for (const auto& [port, key] : {std::pair{s.ports.data, "ports.data"},
                                                {s.ports.position, "ports.position"},
                                                {s.ports.imu, "ports.imu"}})
                    if (port != 0) claim("destination " + s.to + ":" + std::to_string(port), key);
            if (s.source_port != 0)
                claim("source port " + std::to_string(s.source_port), "source_port");
            if (!s.pcap.empty()) claim("pcap file " + s.pcap, "pcap");
        }
    }

    fs::path dir_;
};

}  // namespace

RigConfig load_rig(const std::string& file, const std::string* text) {
    return RigReader(file).run(file, text);
}

}  // namespace mirage::rig
