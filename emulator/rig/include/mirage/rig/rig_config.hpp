// SPDX-License-Identifier: Apache-2.0
// A rig file (docs/rig.md): a vehicle's lidars in one YAML file — the scene, one navigation
// source, and the sensors with their mounts, wire settings, destinations and outputs. Parsing is
// pure: names of presets, files and URIs are checked by the commands that open them.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mirage::rig {

struct Ports {
    std::uint16_t data = 0;      // required with a destination
    std::uint16_t position = 0;  // Velodyne position packets; 0: off
    std::uint16_t imu = 0;       // Ouster IMU packets; 0: off
};

// Faults a sensor starts with and returns to on reset (docs/control.md §5).
struct Faults {
    double drop_rate = 0;      // chance a drop burst starts at a packet, 0..1
    int drop_burst = 1;        // packets per burst, 1..1000
    double range_bias_m = 0;   // ±32.767
    double range_noise_m = 0;  // extra Gaussian σ, 0..10
    bool freeze_nav = false;   // live navigation only: the pose of the moment is held
    bool stale_nav = false;    // as if no navigation arrived: slots without returns
    bool stop = false;         // the sensor sends nothing
};

struct SensorEntry {
    std::string name;                          // unique in the rig: [A-Za-z0-9_-]
    std::string sensor;                        // preset or sensor file (relative to the rig file)
    std::array<double, 3> lever_arm{0, 0, 0};  // m, body frame (x forward, y left, z up)
    std::array<double, 3> boresight{0, 0, 0};  // roll, pitch, yaw in degrees
    std::string return_mode = "strongest";     // Velodyne: strongest, last, dual
    double rpm = 0;                            // Velodyne; 0: the model's default
    std::string profile = "LEGACY";            // Ouster UDP profile
    std::string timestamp_mode = "TIME_FROM_INTERNAL_OSC";  // Ouster (docs/time.md §3)
    std::string to;                                         // destination IPv4 host; empty: none
    std::uint16_t source_port = 0;                          // 0: any
    Ports ports;
    std::string pcap;  // capture of the sensor's packets; empty: none
    std::string las;   // LAS 1.4 of the sensor's rendered points (before faults); empty: none
    std::optional<Faults> faults;  // empty: the rig's `faults`
    int line = 0;                  // where the entry starts in the file (for messages)
};

// A run a controller may select (holding register 1): the rig's navigation with these changes.
struct Scenario {
    std::string name;
    std::string trajectory;  // trajectory rigs only; empty: the rig's
    std::string start;       // empty: the rig's
    std::string duration;    // empty: the rig's
};

// The Modbus control plane (docs/control.md): with it, `mirage rig` waits for commands.
struct Control {
    bool enabled = false;
    std::string tcp = "127.0.0.1:1502";  // host:port; "off": no TCP server
    std::string rtu;                     // serial device or pty; empty: no RTU server
    int baud = 115200;
    char parity = 'N';  // from none, even, odd
    int stop_bits = 1;
    int unit = 1;
    int max_clients = 8;
    int watchdog_ms = 0;              // 0: off
    std::vector<Scenario> scenarios;  // empty: one, the rig as written
};

struct RigConfig {
    std::string file;        // as given
    std::string scene;       // demo or a scene file (relative paths resolved)
    std::string trajectory;  // navigation: trajectory CSV, demo-*, static:… (or empty)
    // …or a recorded navigation log re-simulated as the trajectory (as `emulate --nav-log`),
    std::string nav_log;
    std::string nav_log_protocol = "nmea";  // nmea, novatel, ncom, oxts-can, sbg-can
    // …or live: a `--nav` URI (INS or DIS) with its settings as `mirage live` takes them.
    std::string nav;
    std::vector<double> nav_origin;  // nav, nav_log: lat, lon, h tangent plane; empty: the scene's
    double max_extrapolation_ms = 50;  // beyond the newest sample: stale
    // > 0: send nothing until the first full pose and fail without one by then; 0: stream
    // without returns on the host's clock until it comes (docs/rig.md §2).
    double first_nav_timeout_s = 0;
    std::string start;     // UTC / gps: time of the first pulse; empty: now
    std::string duration;  // seconds; empty: the trajectory's span (static: until Ctrl-C)
    int threads = 1;       // render threads per sensor
    Faults faults;         // every sensor's, unless it gives its own
    Control control;
    std::vector<SensorEntry> sensors;
};

// Reads and checks a rig file: unknown keys, types and ranges, unique names, and no two sensors
// claiming the same destination address and port or the same source port. Throws ConfigError
// "rig '<file>': <key path>: <problem> (line N)". `text`: the YAML itself (tests), or nullptr.
RigConfig load_rig(const std::string& file, const std::string* text = nullptr);

}  // namespace mirage::rig
