// SPDX-License-Identifier: Apache-2.0
// Rig files (docs/rig.md §1): the example loads; every mistake is refused naming the file, the
// key path and the line; no two sensors claim one destination or source port.
#include "mirage/rig/rig_config.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::rig {
namespace {

const std::string kGood = R"(scene: yard.yaml
navigation:
  trajectory: static:0,0,1.8,0,0,30
duration: 2.5
threads: 2
sensors:
  - name: left
    sensor: vlp16
    return_mode: dual
    rpm: 900
    mount: {lever_arm: [1, 0.5, 0.3], boresight: [0, 0, 90]}
    to: 127.0.0.1
    source_port: 40001
    ports: {data: 2368, position: 8308}
  - name: roof
    sensor: sensors/os.yaml
    profile: RNG19_RFL8_SIG16_NIR16
    to: 127.0.0.1
    ports: {data: 7502, imu: 7503}
    pcap: out/roof.pcap
)";

TEST(RigConfig, a_rig_file_loads_with_paths_relative_to_it) {
    const RigConfig c = load_rig("/bench/car.yaml", &kGood);
    EXPECT_EQ(c.scene, "/bench/yard.yaml");
    EXPECT_EQ(c.trajectory, "static:0,0,1.8,0,0,30");
    EXPECT_EQ(c.duration, "2.5");
    EXPECT_EQ(c.threads, 2);
    ASSERT_EQ(c.sensors.size(), 2u);
    const SensorEntry& l = c.sensors[0];
    EXPECT_EQ(l.name, "left");
    EXPECT_EQ(l.sensor, "vlp16");  // a preset stays a name
    EXPECT_EQ(l.return_mode, "dual");
    EXPECT_EQ(l.rpm, 900);
    EXPECT_EQ(l.lever_arm[1], 0.5);
    EXPECT_EQ(l.boresight[2], 90);
    EXPECT_EQ(l.source_port, 40001);
    EXPECT_EQ(l.ports.data, 2368);
    EXPECT_EQ(l.ports.position, 8308);
    EXPECT_EQ(l.line, 7);
    const SensorEntry& r = c.sensors[1];
    EXPECT_EQ(r.sensor, "/bench/sensors/os.yaml");
    EXPECT_EQ(r.pcap, "/bench/out/roof.pcap");
    EXPECT_EQ(r.ports.imu, 7503);
}

TEST(RigConfig, a_live_navigation_source_takes_mirage_live_settings) {
    std::string text = kGood;
    text.replace(text.find("  trajectory: static:0,0,1.8,0,0,30"), 35,
                 "  nav: 'dis:udp://:3000?entity=1.2.3'\n  origin: [48.1, 11.5, 520]\n"
                 "  max_extrapolation_ms: 150\n  first_nav_timeout: 30");
    const RigConfig c = load_rig("car.yaml", &text);
    EXPECT_TRUE(c.trajectory.empty());
    EXPECT_EQ(c.nav, "dis:udp://:3000?entity=1.2.3");
    EXPECT_EQ(c.nav_origin, (std::vector<double>{48.1, 11.5, 520}));
    EXPECT_EQ(c.max_extrapolation_ms, 150);
    EXPECT_EQ(c.first_nav_timeout_s, 30);
}

TEST(RigConfig, a_navigation_log_is_a_trajectory_on_its_own_times) {
    std::string text = kGood;
    text.replace(text.find("  trajectory: static:0,0,1.8,0,0,30"), 35,
                 "  nav_log: logs/drive.ncom\n  protocol: ncom\n  origin: [48.1, 11.5, 520]");
    const RigConfig c = load_rig("/bench/car.yaml", &text);
    EXPECT_EQ(c.nav_log, "/bench/logs/drive.ncom");
    EXPECT_EQ(c.nav_log_protocol, "ncom");
    EXPECT_EQ(c.nav_origin.size(), 3u);
    EXPECT_TRUE(c.trajectory.empty() && c.nav.empty());
}

TEST(RigConfig, a_control_plane_scenarios_and_default_faults) {
    std::string text = kGood;
    text.replace(text.find("threads: 2"), 10,
                 "threads: 2\nfaults: {range_bias: -0.25, drop_rate: 0.01, drop_burst: 4}\n"
                 "control:\n  tcp: 127.0.0.1:0\n  rtu: /dev/ttyUSB0\n  parity: even\n"
                 "  unit: 17\n  watchdog_ms: 500\n  scenarios:\n    - {name: base}\n"
                 "    - {name: fast, trajectory: demo-car, duration: 4}");
    text.replace(text.find("    pcap: out/roof.pcap"), 23,
                 "    pcap: out/roof.pcap\n    faults: {stop: true}");
    const RigConfig c = load_rig("car.yaml", &text);
    EXPECT_TRUE(c.control.enabled);
    EXPECT_EQ(c.control.tcp, "127.0.0.1:0");
    EXPECT_EQ(c.control.rtu, "/dev/ttyUSB0");
    EXPECT_EQ(c.control.parity, 'E');
    EXPECT_EQ(c.control.unit, 17);
    EXPECT_EQ(c.control.watchdog_ms, 500);
    ASSERT_EQ(c.control.scenarios.size(), 2u);
    EXPECT_EQ(c.control.scenarios[1].trajectory, "demo-car");
    EXPECT_EQ(c.control.scenarios[1].duration, "4");
    EXPECT_EQ(c.faults.range_bias_m, -0.25);
    EXPECT_EQ(c.faults.drop_burst, 4);
    EXPECT_FALSE(c.sensors[0].faults.has_value());
    ASSERT_TRUE(c.sensors[1].faults.has_value());
    EXPECT_TRUE(c.sensors[1].faults->stop);
    EXPECT_FALSE(load_rig("car.yaml", &kGood).control.enabled);  // no section: no server
}

TEST(RigConfig, the_example_in_recordings_loads) {
    const RigConfig c =
        load_rig(std::string(MIRAGE_SOURCE_DIR) + "/recordings/rigs/car-five-lidars.yaml");
    EXPECT_EQ(c.sensors.size(), 5u);
    EXPECT_EQ(c.trajectory, "demo-car");
    const RigConfig b =
        load_rig(std::string(MIRAGE_SOURCE_DIR) + "/recordings/rigs/bench-controlled.yaml");
    EXPECT_TRUE(b.control.enabled);
    EXPECT_EQ(b.control.scenarios.size(), 2u);
    EXPECT_EQ(b.faults.range_noise_m, 0.005);
    ASSERT_TRUE(b.sensors[1].faults.has_value());
    EXPECT_EQ(b.sensors[1].faults->range_noise_m, 0);  // its own: none
}

// `from` replaced by `to` in the good file must fail with a message holding every `want`.
void expect_refused(const std::string& from, const std::string& to,
                    std::initializer_list<const char*> want) {
    std::string text = kGood;
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    try {
        (void)load_rig("car.yaml", &text);
        ADD_FAILURE() << "accepted: " << to;
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("rig 'car.yaml'"), std::string::npos) << m;
        for (const char* w : want) EXPECT_NE(m.find(w), std::string::npos) << w << " in: " << m;
    }
}

TEST(RigConfig, mistakes_name_the_key_path_and_line) {
    expect_refused("threads: 2", "threads: 2\ncontrols: {}", {"controls: unknown key", "(line 6)"});
    expect_refused("    rpm: 900", "    rpm: 9000", {"sensors[0].rpm", "(line 10)"});
    expect_refused("return_mode: dual", "return_mode: both",
                   {"sensors[0].return_mode", "strongest, last or dual", "(line 9)"});
    expect_refused("[1, 0.5, 0.3]", "[1, 0.5]", {"sensors[0].mount.lever_arm", "3 numbers"});
    expect_refused("[1, 0.5, 0.3]", "[1, 500, 0.3]", {"sensors[0].mount.lever_arm[1]"});
    expect_refused("ports: {data: 7502, imu: 7503}", "ports: {imu: 7503}",
                   {"sensors[1].ports.data", "missing"});
    expect_refused("    to: 127.0.0.1\n    source_port", "    source_port",
                   {"sensors[0]", "nowhere to go"});
    expect_refused("name: left", "name: 'le ft'", {"sensors[0].name", "letters"});
    expect_refused("duration: 2.5", "duration: -1", {"duration", "positive"});
    expect_refused("navigation:\n  trajectory", "navigation:\n  path", {"navigation.path"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30",
                   "  trajectory: a.csv\n  nav: ncom:udp://:3000",
                   {"navigation", "one of trajectory"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30",
                   "  trajectory: a.csv\n  origin: [1, 2, 3]", {"navigation.origin", "nav only"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30", "  nav: x\n  origin: [91, 2, 3]",
                   {"navigation.origin", "latitude"});
    expect_refused("sensors:", "sensor_list:", {"sensor_list: unknown key"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30", "  nav_log: a.nmea\n  protocol: gsof",
                   {"navigation.protocol", "nmea, novatel"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30", "  nav_log: a.nmea\n  trajectory: b.csv",
                   {"navigation", "nav_log"});
    expect_refused("threads: 2", "threads: 2\ncontrol: {watchdog_ms: 50}",
                   {"control.watchdog_ms", "100..60000", "(line 6)"});
    expect_refused("threads: 2", "threads: 2\ncontrol: {parity: mark}", {"control.parity"});
    expect_refused("threads: 2", "threads: 2\ncontrol: {tcp: 'off'}", {"control.tcp", "no rtu"});
    expect_refused("threads: 2", "threads: 2\ncontrol: {scenarios: [{trajectory: x}]}",
                   {"control.scenarios[0].name", "missing"});
    expect_refused("threads: 2", "threads: 2\nfaults: {drop_rate: 0.00001}",
                   {"faults.drop_rate", "0.0001"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30",
                   "  nav_log: a.nmea\ncontrol: {scenarios: [{name: a, trajectory: demo-car}]}",
                   {"control.scenarios[0].trajectory", "navigation log"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30",
                   "  nav: ncom:udp://:3000\ncontrol: {scenarios: [{name: a, start: now}]}",
                   {"control.scenarios[0].start", "live source"});
    expect_refused("  trajectory: static:0,0,1.8,0,0,30", "  nav: ncom:udp://:3000\nstart: now",
                   {"start", "live source"});
    expect_refused("threads: 2", "threads: 2\nfaults: {freeze_nav: true}",
                   {"faults.freeze_nav", "live navigation"});
    expect_refused("    pcap: out/roof.pcap", "    pcap: out/roof.pcap\n    faults: {drop_rate: 2}",
                   {"sensors[1].faults.drop_rate"});
    expect_refused("scene: yard.yaml", "scene: [a, b]", {"scene", "non-empty string"});
    expect_refused("duration: 2.5", "duration: 2.5\nduration: 3", {"duplicate key"});
    expect_refused("threads: 2\n", "threads: 2\n  oops: [\n", {"YAML syntax error", "line"});
}

TEST(RigConfig, two_sensors_may_not_claim_one_port) {
    expect_refused("name: roof", "name: left", {"sensors[1].name", "'left' is also sensors[0]"});
    expect_refused(
        "{data: 7502, imu: 7503}", "{data: 7502, imu: 8308}",
        {"sensors[1].ports.imu", "destination 127.0.0.1:8308", "claimed by sensor 'left'"});
    expect_refused("{data: 7502, imu: 7503}", "{data: 2368}",
                   {"sensors[1].ports.data", "127.0.0.1:2368"});
    expect_refused("    pcap: out/roof.pcap", "    pcap: out/roof.pcap\n    source_port: 40001",
                   {"sensors[1].source_port", "source port 40001"});
}

TEST(RigConfig, two_sensors_may_not_write_one_capture) {
    std::string text = kGood;
    text.replace(text.find("    source_port: 40001\n"), 0, "    pcap: out/roof.pcap\n");
    try {
        (void)load_rig("/b/car.yaml", &text);
        ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("sensors[1].pcap: pcap file /b/out/roof.pcap is also "
                                             "claimed by sensor 'left'"),
                  std::string::npos)
            << e.what();
    }
}

TEST(RigConfig, the_same_port_on_another_host_is_no_clash) {
    std::string text = kGood;
    text.replace(text.find("{data: 7502, imu: 7503}"), 23, "{data: 2368}");
    text.replace(text.rfind("to: 127.0.0.1"), 13, "to: 127.0.0.2");
    EXPECT_NO_THROW((void)load_rig("car.yaml", &text));
}

}  // namespace
}  // namespace mirage::rig
