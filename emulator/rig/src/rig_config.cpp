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
        check_keys(root, "",
                   {"scene", "navigation", "start", "duration", "threads", "faults", "control",
                    "sensors"});
        RigConfig c;
        c.file = file;
        if (!root["scene"]) fail("scene", "missing (demo or a scene file)", root);
        const std::string scene = string(root["scene"], "scene");
        c.scene = scene == "demo" ? scene : file_path(scene);
        navigation(root["navigation"], c);
        if (root["start"] && !c.nav.empty())  // a live source's time is the INS's
            fail("start", "the rig's navigation is a live source", root["start"]);
        if (root["start"]) c.start = string(root["start"], "start");
        if (root["duration"]) {
            (void)positive(root["duration"], "duration");
            c.duration = root["duration"].Scalar();  // kept as text: exact decimal seconds
        }
        if (root["threads"])
            c.threads = static_cast<int>(integer(root["threads"], "threads", 1, 64));
        if (root["faults"]) c.faults = faults(root["faults"], "faults", !c.nav.empty());
        if (root["control"]) control(root["control"], c);
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
                   {"trajectory", "nav", "nav_log", "protocol", "origin", "max_extrapolation_ms",
                    "first_nav_timeout"});
        if (int(bool(n["trajectory"])) + int(bool(n["nav"])) + int(bool(n["nav_log"])) != 1)
            fail(p,
                 "give one of trajectory (a path), nav_log (a recorded log) or nav (a live "
                 "source's URI)",
                 n);
        if (n["protocol"] && !n["nav_log"]) fail(sub(p, "protocol"), "applies to nav_log", n);
        if (n["nav_log"]) {
            for (const char* k : {"max_extrapolation_ms", "first_nav_timeout"})
                if (n[k]) fail(sub(p, k), "applies to nav only", n[k]);
            c.nav_log = file_path(string(n["nav_log"], sub(p, "nav_log")));
            if (n["protocol"]) {
                c.nav_log_protocol = string(n["protocol"], sub(p, "protocol"));
                const std::string& q = c.nav_log_protocol;
                if (q != "nmea" && q != "novatel" && q != "ncom" && q != "oxts-can" &&
                    q != "sbg-can")
                    fail(sub(p, "protocol"), "expected nmea, novatel, ncom, oxts-can or sbg-can",
                         n["protocol"]);
            }
            origin(n, c);
            return;
        }
        if (n["trajectory"]) {
            for (const char* k : {"origin", "max_extrapolation_ms", "first_nav_timeout"})
                if (n[k]) fail(sub(p, k), "applies to nav only", n[k]);
            const std::string t = string(n["trajectory"], sub(p, "trajectory"));
            c.trajectory = t.starts_with("demo-") || t.starts_with("static:") ? t : file_path(t);
            return;
        }
        c.nav = string(n["nav"], sub(p, "nav"));
        origin(n, c);
        if (n["max_extrapolation_ms"])
            c.max_extrapolation_ms =
                number_in(n["max_extrapolation_ms"], sub(p, "max_extrapolation_ms"), 0, 10'000);
        if (n["first_nav_timeout"])
            c.first_nav_timeout_s =
                number_in(n["first_nav_timeout"], sub(p, "first_nav_timeout"), 0.1, 3600);
    }

    Faults faults(const YAML::Node& n, const std::string& path, bool live) const {
        require_map(n, path);
        check_keys(n, path,
                   {"drop_rate", "drop_burst", "range_bias", "range_noise", "freeze_nav",
                    "stale_nav", "stop"});
        Faults f;
        const auto key = [&](const char* k) { return sub(path, k); };
        if (n["drop_rate"]) f.drop_rate = number_in(n["drop_rate"], key("drop_rate"), 0, 1);
        if (f.drop_rate > 0 && f.drop_rate < 0.00005)  // would round to 0 in 1/10000
            fail(key("drop_rate"), "0, or at least 0.0001 (the control plane's step)",
                 n["drop_rate"]);
        if (n["drop_burst"])
            f.drop_burst = static_cast<int>(integer(n["drop_burst"], key("drop_burst"), 1, 1000));
        if (n["range_bias"])
            f.range_bias_m = number_in(n["range_bias"], key("range_bias"), -32.767, 32.767);
        if (n["range_noise"])
            f.range_noise_m = number_in(n["range_noise"], key("range_noise"), 0, 10);
        if (n["freeze_nav"]) f.freeze_nav = boolean(n["freeze_nav"], key("freeze_nav"));
        if (f.freeze_nav && !live)
            fail(key("freeze_nav"), "applies to a live navigation source (navigation.nav)",
                 n["freeze_nav"]);
        if (n["stale_nav"]) f.stale_nav = boolean(n["stale_nav"], key("stale_nav"));
        if (n["stop"]) f.stop = boolean(n["stop"], key("stop"));
        return f;
    }

    void control(const YAML::Node& n, RigConfig& c) const {
        const std::string p = "control";
        require_map(n, p);
        check_keys(n, p,
                   {"tcp", "rtu", "baud", "parity", "stop_bits", "unit", "max_clients",
                    "watchdog_ms", "scenarios"});
        Control& k = c.control;
        k.enabled = true;
        if (n["tcp"]) k.tcp = string(n["tcp"], sub(p, "tcp"));
        if (n["rtu"]) k.rtu = string(n["rtu"], sub(p, "rtu"));
        if (k.tcp == "off" && k.rtu.empty()) fail(sub(p, "tcp"), "off, and no rtu line either", n);
        if (n["baud"])
            k.baud = static_cast<int>(integer(n["baud"], sub(p, "baud"), 1200, 4'000'000));
        if (n["parity"]) {
            const std::string par = string(n["parity"], sub(p, "parity"));
            if (par != "none" && par != "even" && par != "odd")
                fail(sub(p, "parity"), "expected none, even or odd", n["parity"]);
            k.parity = par == "none" ? 'N' : par == "even" ? 'E' : 'O';
        }
        if (n["stop_bits"])
            k.stop_bits = static_cast<int>(integer(n["stop_bits"], sub(p, "stop_bits"), 1, 2));
        if (n["unit"]) k.unit = static_cast<int>(integer(n["unit"], sub(p, "unit"), 1, 247));
        if (n["max_clients"])
            k.max_clients =
                static_cast<int>(integer(n["max_clients"], sub(p, "max_clients"), 1, 64));
        if (n["watchdog_ms"]) {
            k.watchdog_ms =
                static_cast<int>(integer(n["watchdog_ms"], sub(p, "watchdog_ms"), 0, 60000));
            if (k.watchdog_ms != 0 && k.watchdog_ms < 100)
                fail(sub(p, "watchdog_ms"), "0 (off) or 100..60000", n["watchdog_ms"]);
        }
        if (n["scenarios"]) scenarios(n["scenarios"], sub(p, "scenarios"), c);
    }

    void scenarios(const YAML::Node& n, const std::string& path, RigConfig& c) const {
        if (!n.IsSequence() || n.size() == 0 || n.size() > 100)
            fail(path, "expected a list of 1 to 100 scenarios", n);
        for (std::size_t i = 0; i < n.size(); ++i) {
            const std::string ip = item(path, i);
            const YAML::Node& s = n[i];
            require_map(s, ip);
            check_keys(s, ip, {"name", "trajectory", "start", "duration"});
            Scenario x;
            if (!s["name"]) fail(sub(ip, "name"), "missing", s);
            x.name = string(s["name"], sub(ip, "name"));
            if (s["trajectory"]) {
                if (!c.nav.empty() || !c.nav_log.empty())
                    fail(sub(ip, "trajectory"),
                         c.nav.empty() ? "the rig's navigation is a navigation log"
                                       : "the rig's navigation is a live source",
                         s["trajectory"]);
                const std::string t = string(s["trajectory"], sub(ip, "trajectory"));
                x.trajectory =
                    t.starts_with("demo-") || t.starts_with("static:") ? t : file_path(t);
            }
            if (s["start"] && !c.nav.empty())  // a live source's time is the INS's
                fail(sub(ip, "start"), "the rig's navigation is a live source", s["start"]);
            if (s["start"]) x.start = string(s["start"], sub(ip, "start"));
            if (s["duration"]) {
                (void)positive(s["duration"], sub(ip, "duration"));
                x.duration = s["duration"].Scalar();
            }
            c.control.scenarios.push_back(x);
        }
    }

    void origin(const YAML::Node& n, RigConfig& c) const {
        const std::string p = "navigation.origin";
        if (!n["origin"]) return;
        c.nav_origin = numbers(n["origin"], p, 3);
        if (std::abs(c.nav_origin[0]) > 90 || std::abs(c.nav_origin[1]) > 180)
            fail(p, "latitude within ±90°, longitude within ±180°", n["origin"]);
    }

    void sensors(const YAML::Node& n, const YAML::Node& root, RigConfig& c) {
        live_ = !c.nav.empty();
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
                    "ports", "pcap", "las", "faults", "timestamp_mode"});
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
        if (n["timestamp_mode"]) {
            s.timestamp_mode = string(n["timestamp_mode"], sub(path, "timestamp_mode"));
            if (s.timestamp_mode != "TIME_FROM_INTERNAL_OSC" &&
                s.timestamp_mode != "TIME_FROM_SYNC_PULSE_IN" &&
                s.timestamp_mode != "TIME_FROM_PTP_1588")
                fail(sub(path, "timestamp_mode"),
                     "expected TIME_FROM_INTERNAL_OSC, TIME_FROM_SYNC_PULSE_IN or "
                     "TIME_FROM_PTP_1588",
                     n["timestamp_mode"]);
        }
        if (n["to"]) s.to = string(n["to"], sub(path, "to"));
        if (n["source_port"]) s.source_port = port(n["source_port"], sub(path, "source_port"));
        if (n["ports"]) ports(n["ports"], sub(path, "ports"), s.ports);
        if (n["pcap"]) s.pcap = file_path(string(n["pcap"], sub(path, "pcap")));
        if (n["las"]) s.las = file_path(string(n["las"], sub(path, "las")));
        if (n["faults"]) s.faults = faults(n["faults"], sub(path, "faults"), live_);
        if (s.to.empty() && s.pcap.empty() && s.las.empty())
            fail(path, "sensor '" + s.name + "' has nowhere to go: give `to`, `pcap` or `las`", n);
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
            if (!s.las.empty()) claim("LAS file " + s.las, "las");
        }
    }

    fs::path dir_;
    bool live_ = false;  // navigation from a live source (freeze_nav allowed)
};

}  // namespace

RigConfig load_rig(const std::string& file, const std::string* text) {
    return RigReader(file).run(file, text);
}

}  // namespace mirage::rig
