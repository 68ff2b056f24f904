// SPDX-License-Identifier: Apache-2.0
// `mirage rig` under its Modbus control plane (issue 22 item 4): a controller arms and starts a
// running rig of two VLP-16s, injects faults (a 2 m range bias on one sensor, stopping the
// other), reads its counters and stops it — libmodbus in-process over TCP, then the independent
// clients mbpoll (TCP and RTU over a socat pty pair) and pymodbus; misbehaving clients leave it
// answering and streaming; a silent controller trips the watchdog into the safe state.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <regex>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "live_yard.hpp"
#include "mirage/core/pose.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kDeg = M_PI / 180;

// A loopback receiver whose packets the test may look at while it runs.
class Receiver {
  public:
    Receiver() : thread_([this] { run(); }) {}
    ~Receiver() {
        stop_ = true;
        thread_.join();
    }
    std::uint16_t port() const { return rx_.port(); }
    std::size_t count() const { return n_.load(); }
    // Packets from index `from` on.
    std::vector<std::vector<std::uint8_t>> since(std::size_t from) const {
        std::lock_guard lk(m_);
        return {packets_.begin() + std::ptrdiff_t(std::min(from, packets_.size())), packets_.end()};
    }

  private:
    void run() {
        udp::ReceivedDatagram d;
        while (!stop_)
            if (rx_.receive(d, std::chrono::milliseconds(20))) {
                std::lock_guard lk(m_);
                packets_.push_back(d.payload);
                ++n_;
            }
    }
    udp::UdpReceiver rx_;
    std::atomic<bool> stop_{false};
    std::atomic<std::size_t> n_{0};
    mutable std::mutex m_;
    std::vector<std::vector<std::uint8_t>> packets_;
    std::thread thread_;
};

// `mirage rig` in the background with its pid (the controlled rig runs until SIGINT).
struct RigProcess {
    BackgroundMirage b;
    pid_t pid = -1;
    int port = -1;
    // `shell`: commands run before mirage replaces the shell (limits, signal dispositions).
    explicit RigProcess(const std::string& rig_file, const std::string& shell = "") {
        b.pipe = ::popen((shell + "echo pid $$; exec " + std::string(MIRAGE_EXE) + " rig " +
                          rig_file + " --no-status 2>&1")
                             .c_str(),
                         "r");
        std::smatch m;
        std::string l = b.wait_for(std::regex("^pid "));
        if (std::regex_search(l, m, std::regex("pid ([0-9]+)"))) pid = std::stoi(m[1]);
        l = b.wait_for(std::regex("control plane: "));
        if (std::regex_search(l, m, std::regex("tcp 127\\.0\\.0\\.1:([0-9]+)")))
            port = std::stoi(m[1]);
    }
    int interrupt() {
        if (pid > 0) ::kill(pid, SIGINT);
        return b.finish();
    }
};

std::string rig_text(std::uint16_t left, std::uint16_t rear, const std::string& control) {
    return "scene: yard.yaml\n"
           "navigation: {trajectory: 'static:2,-3,1.8,0,0,30'}\n"
           "duration: 60\n"
           "control:\n" +
           control +
           "sensors:\n"
           "  - name: left\n"
           "    sensor: vlp16\n"
           "    mount: {lever_arm: [1, 0.5, 0.3], boresight: [0, 0, 90]}\n"
           "    to: 127.0.0.1\n"
           "    ports: {data: " +
           std::to_string(left) +
           "}\n"
           "  - name: rear\n"
           "    sensor: vlp16\n"
           "    mount: {lever_arm: [-1, 0, 0.5], boresight: [0, 10, 180]}\n"
           "    to: 127.0.0.1\n"
           "    ports: {data: " +
           std::to_string(rear) + "}\n";
}

// Median distance from the yard of the packets' points, all placed with one pose.
double median_with_pose(const std::vector<std::vector<std::uint8_t>>& packets,
                        const core::Pose& pose) {
    std::vector<double> err;
    velodyne::DecodedPacket dp;
    for (const auto& p : packets) {
        if (p.size() != 1206 || velodyne::decode_data(p, nullptr, dp) != velodyne::DecodeStatus::Ok)
            continue;
        for (const auto& f : dp.firing)
            if (f.distance_m > 0) err.push_back(distance_to_yard(pose.apply({f.x, f.y, f.z})));
    }
    if (err.empty()) return -1;
    std::nth_element(err.begin(), err.begin() + std::ptrdiff_t(err.size() / 2), err.end());
    return err[err.size() / 2];
}

// Median distance of the packets' points from the yard, placed with platform ∘ mount.
double median_off_yard(const std::vector<std::vector<std::uint8_t>>& packets,
                       const core::Pose& mount) {
    const core::Pose platform{{2, -3, 1.8}, core::quaternion_from_rpy(0, 0, 30 * kDeg)};
    return median_with_pose(packets, platform * mount);
}

const core::Pose kRearMount{{-1, 0, 0.5}, core::quaternion_from_rpy(0, 10 * kDeg, 180 * kDeg)};

// Waits until `pred` holds or `seconds` pass.
template <class Pred>
bool eventually(Pred pred, double seconds = 5) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < deadline) {
        if (pred()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return pred();
}

// Seconds from `since` to the last packet `rx` received, once it has been quiet for 300 ms.
double quiet_after(const Receiver& rx, Clock::time_point since) {
    std::size_t n = rx.count();
    auto last = Clock::now();
    while (Clock::now() - last < std::chrono::milliseconds(300)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (rx.count() != n) {
            n = rx.count();
            last = Clock::now();
        }
    }
    return std::chrono::duration<double>(last - since).count();
}

struct ModbusClient {
    modbus_t* c = nullptr;
    explicit ModbusClient(int port) {
        c = modbus_new_tcp("127.0.0.1", port);
        EXPECT_EQ(modbus_connect(c), 0) << modbus_strerror(errno);
    }
    ~ModbusClient() {
        modbus_close(c);
        modbus_free(c);
    }
    std::uint16_t in(int address) {
        std::uint16_t v = 0xFFFF;
        EXPECT_EQ(modbus_read_input_registers(c, address, 1, &v), 1) << modbus_strerror(errno);
        return v;
    }
    std::uint32_t in32(int address) {
        std::array<std::uint16_t, 2> v{};
        EXPECT_EQ(modbus_read_input_registers(c, address, 2, v.data()), 2);
        return std::uint32_t(v[0]) << 16 | v[1];
    }
    int write(int address, std::uint16_t v) { return modbus_write_register(c, address, v); }
};

std::uint64_t fnv1a(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (std::istreambuf_iterator<char> it(in), end; it != end; ++it) {
        h ^= static_cast<unsigned char>(*it);
        h *= 0x100000001b3ull;
    }
    return h;
}

// Sensor blocks: input registers 100 + 20 i, holding (faults) 100 + 10 i (docs/control.md §2).
constexpr int kLeft = 0, kRear = 1;
int sensor_in(int s, int off) { return 100 + 20 * s + off; }
int fault_hr(int s, int off) { return 100 + 10 * s + off; }

// A controlled rig of one VLP-16 on a DIS entity; `nav_keys`: more `navigation` keys.
std::string dis_rig(std::uint16_t data, const std::string& nav_keys) {
    return "scene: yard.yaml\n"
           "navigation: {nav: 'dis:udp://127.0.0.1:0?entity=1.1.1', " +
           nav_keys +
           "}\n"
           "control: {tcp: '127.0.0.1:0'}\n"
           "sensors:\n"
           "  - {name: roof, sensor: vlp16, to: 127.0.0.1, ports: {data: " +
           std::to_string(data) + "}}\n";
}

// Arms and starts the rig; the UDP port its DIS reader listens on (0 when none was printed).
int arm_start_dis(RigProcess& rig, ModbusClient& mb) {
    EXPECT_EQ(mb.write(0, 1), 1);
    EXPECT_EQ(mb.write(0, 2), 1);
    std::smatch m;
    const std::string l = rig.b.wait_for(std::regex("udp port [0-9]+"), 10);
    return std::regex_search(l, m, std::regex("udp port ([0-9]+)")) ? std::stoi(m[1].str()) : 0;
}

TEST(RigControl, a_controller_arms_starts_faults_reads_and_stops_a_running_rig) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Receiver left, rear;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << rig_text(left.port(), rear.port(), "  tcp: 127.0.0.1:0\n");
    }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    // Identity: product, version, the rig file's hash; idle; nothing sent.
    EXPECT_EQ(mb.in(0), 0x4D52);
    const std::uint64_t h = fnv1a(tmp.file("rig.yaml"));
    EXPECT_EQ(mb.in(4), std::uint16_t(h >> 48));
    EXPECT_EQ(mb.in(7), std::uint16_t(h));
    EXPECT_EQ(mb.in(8), 0);
    EXPECT_EQ(mb.in(12), 2);
    // Start before arm: server busy; still idle, nothing sent.
    EXPECT_EQ(mb.write(0, 2), -1);
    EXPECT_EQ(errno, EMBXSBUSY);
    EXPECT_EQ(mb.in(9), 1);  // last error: command not allowed in this state
    ASSERT_EQ(mb.write(0, 1), 1);
    EXPECT_EQ(mb.in(8), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(left.count() + rear.count(), 0u);
    ASSERT_EQ(mb.write(0, 2), 1);
    EXPECT_EQ(mb.in(8), 2);
    ASSERT_TRUE(eventually([&] { return rear.count() > 700 && left.count() > 700; }))
        << rig.b.output;
    const double before = median_off_yard(rear.since(0), kRearMount);
    // Fault: rear's ranges 2 m long; left stops sending.
    ASSERT_EQ(mb.write(fault_hr(kRear, 3), 2000), 1);
    const auto left_stop_at = Clock::now();
    ASSERT_EQ(mb.write(fault_hr(kLeft, 6), 1), 1);
    const double left_quiet_s = quiet_after(left, left_stop_at);
    std::this_thread::sleep_for(std::chrono::milliseconds(400));  // rear's biased packets arrive
    const std::size_t rear_mark = rear.count(), left_mark = left.count();
    ASSERT_TRUE(eventually([&] { return rear.count() > rear_mark + 700; })) << rig.b.output;
    const double after = median_off_yard(rear.since(rear_mark), kRearMount);
    EXPECT_EQ(left.count(), left_mark);        // stopped
    EXPECT_EQ(mb.in(sensor_in(kLeft, 0)), 2);  // left: stopped
    EXPECT_EQ(mb.in(sensor_in(kRear, 0)), 1);  // rear: streaming
    const std::uint32_t rear_packets = mb.in32(sensor_in(kRear, 2));
    EXPECT_GE(rear_packets, rear.count() - 10);
    EXPECT_GT(mb.in32(sensor_in(kRear, 4)), 300u * rear_packets);  // points
    // A misbehaving client meanwhile: junk, a bad header, a half frame; the rig streams on.
    {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(std::uint16_t(rig.port));
        ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
        ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
        const std::uint8_t junk[] = {0, 1, 0x55, 0x55, 0, 6, 1, 3, 0, 0};
        (void)::send(fd, junk, sizeof junk, MSG_NOSIGNAL);
        ::close(fd);
    }
    const std::size_t mark2 = rear.count();
    EXPECT_TRUE(eventually([&] { return rear.count() > mark2 + 300; }));
    EXPECT_EQ(mb.in(8), 2);
    std::printf(
        "[ rig control ] rear median off the yard: %.4f m before, %.4f m with a 2 m bias; "
        "left stopped at %zu packets, its last %.3f s after the stop fault; rear %u packets by "
        "its counter\n",
        before, after, left_mark, left_quiet_s, rear_packets);
    EXPECT_LT(left_quiet_s, 0.15);
    EXPECT_LT(before, 0.02);
    EXPECT_GT(after, 0.5);
    // Stop: stopped; the packets queued with the sender are dropped, nothing more arrives.
    const auto stop_at = Clock::now();
    ASSERT_EQ(mb.write(0, 3), 1);
    ASSERT_TRUE(eventually([&] { return mb.in(8) == 3; }));
    const double drain_s = quiet_after(rear, stop_at);
    const std::size_t end_mark = rear.count();
    std::printf("[ rig control ] last packet %.3f s after the stop command\n", drain_s);
    EXPECT_LT(drain_s, 0.15);  // the queue is dropped, not drained (docs/control.md §4)
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(rear.count(), end_mark);
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
    EXPECT_NE(rig.b.output.find("withheld"), std::string::npos) << rig.b.output;
    EXPECT_NE(rig.b.output.find("1 closed malformed"), std::string::npos) << rig.b.output;
}

TEST(RigControl, a_silent_controller_trips_the_watchdog_into_the_safe_state) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Receiver left, rear;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << rig_text(left.port(), rear.port(), "  tcp: 127.0.0.1:0\n  watchdog_ms: 400\n");
    }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    ASSERT_EQ(mb.write(0, 1), 1);
    ASSERT_EQ(mb.write(0, 2), 1);
    // Heartbeats for a second keep it running.
    auto silent = Clock::now();
    for (int i = 0; i < 10; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        ASSERT_EQ(mb.write(2, std::uint16_t(i)), 1);
        silent = Clock::now();
    }
    EXPECT_EQ(mb.in(8), 2);
    EXPECT_GT(rear.count(), 0u);
    // Silence: fault (4), last error 4 (watchdog), one expiry; the streams end.
    ASSERT_TRUE(eventually([&] { return mb.in(8) == 4; }, 3));
    const double tripped_s = std::chrono::duration<double>(Clock::now() - silent).count();
    EXPECT_EQ(mb.in(9), 4);
    EXPECT_EQ(mb.in(13), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const std::size_t mark = left.count() + rear.count();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(left.count() + rear.count(), mark);
    EXPECT_EQ(mb.write(0, 1), -1);  // only reset leaves the fault
    ASSERT_EQ(mb.write(0, 4), 1);
    EXPECT_EQ(mb.in(8), 0);
    EXPECT_EQ(mb.in(9), 0);
    std::printf("[ rig watchdog ] 400 ms watchdog: fault seen %.3f s after the last heartbeat\n",
                tripped_s);
    EXPECT_GT(tripped_s, 0.39);  // the server stamps the heartbeat before the reply
    EXPECT_LT(tripped_s, 0.6);   // the supervisor ticks every 10 ms
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
}

// Stop, select another scenario, arm and start while the first run is still shutting down: the
// second run starts with the new scenario and keeps running (its predecessor's end does not
// stop it).
TEST(RigControl, a_restart_during_the_previous_runs_shutdown_runs_the_new_scenario) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Receiver left, rear;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << rig_text(left.port(), rear.port(),
                        "  tcp: 127.0.0.1:0\n  scenarios:\n    - {name: a}\n"
                        "    - {name: b, trajectory: 'static:6,1,1.8,0,0,-20'}\n");
    }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    ASSERT_EQ(mb.write(0, 1), 1);
    ASSERT_EQ(mb.write(0, 2), 1);
    ASSERT_TRUE(eventually([&] { return rear.count() > 300; })) << rig.b.output;
    ASSERT_EQ(mb.write(0, 3), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the supervisor is joining
    ASSERT_EQ(mb.write(1, 1), 1);
    ASSERT_EQ(mb.write(0, 1), 1);
    ASSERT_EQ(mb.write(0, 2), 1);
    ASSERT_FALSE(rig.b.wait_for(std::regex("run 2, scenario 1"), 10).empty()) << rig.b.output;
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // the first run's packets pass
    const std::size_t from = rear.count();
    ASSERT_TRUE(eventually([&] { return rear.count() > from + 700; })) << rig.b.output;
    const core::Pose b{{6, 1, 1.8}, core::quaternion_from_rpy(0, 0, -20 * kDeg)};
    const double median = median_with_pose(rear.since(from), b * kRearMount);
    const std::uint16_t state = mb.in(8), runs = mb.in(18), scenario = mb.in(10);
    std::printf(
        "[ rig restart ] after stop-arm-start during shutdown: state %u, runs %u, "
        "scenario %u; rear median %.4f m off the yard with scenario b's pose\n",
        state, runs, scenario, median);
    EXPECT_EQ(state, 2);
    EXPECT_EQ(runs, 2);
    EXPECT_EQ(scenario, 1);
    EXPECT_GE(median, 0);
    EXPECT_LT(median, 0.02);
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
}

// A sensor that fails while running (its LAS file hits the file-size limit) takes the rig into
// the safe state at once, duration or not: fault, last error 5, the other sensor stops too; the
// LAS file keeps whole records.
TEST(RigControl, a_sensor_failing_while_running_faults_the_rig) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Receiver left, rear;
    {
        std::string text = rig_text(left.port(), rear.port(), "  tcp: 127.0.0.1:0\n");
        text.replace(text.find("  - name: left\n") + 15, 0, "    las: left.las\n");
        std::ofstream(tmp.file("rig.yaml")) << text;
    }
    // A file-size limit; past it a write fails with EFBIG instead of raising SIGXFSZ.
    RigProcess rig(tmp.file("rig.yaml"), "trap '' XFSZ; ulimit -f 2000; ");
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    ASSERT_EQ(mb.write(0, 1), 1);
    const auto started = Clock::now();
    ASSERT_EQ(mb.write(0, 2), 1);
    ASSERT_TRUE(eventually([&] { return mb.in(8) == 4; }, 10)) << rig.b.output;
    const double fault_s = std::chrono::duration<double>(Clock::now() - started).count();
    EXPECT_EQ(mb.in(9), 5);  // a sensor failed
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const std::size_t mark = rear.count();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(rear.count(), mark);  // the rest of the rig stopped with it
    ASSERT_EQ(mb.write(0, 4), 1);
    EXPECT_EQ(mb.in(8), 0);
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
    const auto las = std::filesystem::file_size(tmp.file("left.las"));
    std::printf(
        "[ rig sensor failure ] fault %.2f s after start; rear stopped at %zu packets; "
        "left.las %ju bytes\n",
        fault_s, mark, std::uintmax_t(las));
    EXPECT_NE(rig.b.output.find("sensor 'left' failed"), std::string::npos) << rig.b.output;
    EXPECT_GT(mark, 0u);
    EXPECT_LE(las, 2000u * 1024);
    const RunResult info = run_mirage("las-info " + tmp.file("left.las"));
    EXPECT_EQ(info.exit_code, 0) << info.output;
}

// While a live rig waits for its first pose (first_nav_timeout), the controller already reads
// the navigation counters: junk datagrams on the DIS port show as rejected.
TEST(RigControl, navigation_counters_read_while_waiting_for_the_first_pose) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Receiver rx;
    { std::ofstream(tmp.file("rig.yaml")) << dis_rig(rx.port(), "first_nav_timeout: 30"); }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    const int dis_port = arm_start_dis(rig, mb);
    ASSERT_GT(dis_port, 0) << rig.b.output;
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(dis_port));
    ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    const std::uint8_t junk[] = {7, 1, 1, 1, 0, 0, 0, 0, 0, 12};
    for (int i = 0; i < 5; ++i)
        ::sendto(fd, junk, sizeof junk, 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::close(fd);
    std::uint32_t rejected = 0;
    EXPECT_TRUE(eventually([&] { return (rejected = mb.in32(32)) >= 5; }));
    std::printf(
        "[ rig waiting ] nav rejected %u while waiting for the first pose; state %u; "
        "packets %zu\n",
        rejected, mb.in(8), rx.count());
    EXPECT_EQ(mb.in(8), 2);     // running, waiting
    EXPECT_EQ(rx.count(), 0u);  // first_nav_timeout: nothing sent before the first pose
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
}

bool have(const char* tool) {
    return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0;
}

std::string sh(const std::string& cmd) {
    std::string out;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    char buf[512];
    while (p && std::fgets(buf, sizeof buf, p)) out += buf;
    if (p) ::pclose(p);
    return out;
}

// Independent clients: mbpoll over TCP arms and starts, pymodbus reads the counters and injects
// a drop fault; mbpoll over RTU (a socat pty pair) stops the rig.
TEST(RigControl, mbpoll_and_pymodbus_drive_the_rig_over_tcp_and_rtu) {
    if (!have("mbpoll") || !have("socat"))
        GTEST_SKIP() << "mbpoll or socat missing (scripts/install-deps)";
    const bool pymodbus =
        std::system("/usr/bin/python3 -c 'import pymodbus.client' 2>/dev/null") == 0;
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    const std::string a = tmp.file("pty-a"), b = tmp.file("pty-b");
    const pid_t socat = ::fork();
    if (socat == 0) {
        const std::string l = "pty,raw,echo=0,link=" + a, r = "pty,raw,echo=0,link=" + b;
        ::execlp("socat", "socat", l.c_str(), r.c_str(), static_cast<char*>(nullptr));
        std::_Exit(127);
    }
    ASSERT_TRUE(
        eventually([&] { return std::filesystem::exists(a) && std::filesystem::exists(b); }));
    Receiver left, rear;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << rig_text(left.port(), rear.port(),
                        "  tcp: 127.0.0.1:0\n  rtu: " + a + "\n  baud: 115200\n  parity: none\n");
    }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    const std::string tcp = "mbpoll -m tcp -p " + std::to_string(rig.port) + " -0 -1 -o 2 ";
    std::string out = sh(tcp + "-t 4 -r 0 127.0.0.1 1");
    EXPECT_NE(out.find("Written 1 references"), std::string::npos) << out;
    out = sh(tcp + "-t 4 -r 0 127.0.0.1 2");
    EXPECT_NE(out.find("Written 1 references"), std::string::npos) << out;
    ASSERT_TRUE(eventually([&] { return rear.count() > 800; })) << rig.b.output;
    out = sh(tcp + "-t 3 -r 8 -c 1 127.0.0.1");
    EXPECT_NE(out.find("[8]: \t2"), std::string::npos) << out;  // running
    // Drop bursts on the rear sensor: 20 % of packets start a burst of 5.
    out = sh(tcp + "-t 4 -r 110 127.0.0.1 2000 5");
    EXPECT_NE(out.find("Written 2 references"), std::string::npos) << out;
    if (pymodbus) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        const std::string py =
            "/usr/bin/python3 -c \"from pymodbus.client import ModbusTcpClient as C; "
            "c = C('127.0.0.1', port=" +
            std::to_string(rig.port) +
            "); c.connect(); "
            "r = c.read_input_registers(120, 14, slave=1).registers; "
            "print('state', r[0], 'packets', r[2] << 16 | r[3], 'dropped', r[12] << 16 | r[13])\"";
        out = sh(py);
        std::smatch m;
        ASSERT_TRUE(
            std::regex_search(out, m, std::regex("state 1 packets ([0-9]+) dropped ([0-9]+)")))
            << out;
        const double dropped = std::stod(m[2]), sent = std::stod(m[1]);
        // A burst starts at 20 % of the packets outside one: share p·b/(1 + p·(b−1)) = 5/9.
        std::printf("[ rig pymodbus ] rear: %.0f packets sent, %.0f dropped\n", sent, dropped);
        EXPECT_GT(dropped, 100);
    } else {
        std::printf("[ rig pymodbus ] skipped: python3-pymodbus not installed\n");
    }
    // RTU: unit 1 on the pty pair stops the rig.
    out = sh("mbpoll -m rtu -b 115200 -P none -a 1 -0 -1 -o 2 -t 4 -r 0 " + b + " 3");
    EXPECT_NE(out.find("Written 1 references"), std::string::npos) << out;
    out = sh("mbpoll -m rtu -b 115200 -P none -a 1 -0 -1 -o 2 -t 3 -r 8 -c 1 " + b);
    EXPECT_NE(out.find("[8]: \t3"), std::string::npos) << out;
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
    ::kill(socat, SIGTERM);
    ::waitpid(socat, nullptr, 0);
}

// A live rig (DIS) under control: freezing navigation holds one pose — the points then fit a
// single pose of the circling car and not the truth at their times — and stale navigation, even
// over a frozen pose, sends packets without returns, counted as a stale period.
TEST(RigControl, frozen_and_stale_navigation_on_a_live_rig) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    write_trajectory(tmp.file("circle.csv"));
    const core::Trajectory truth = circle_truth(tmp.file("circle.csv"));
    Receiver rx;
    { std::ofstream(tmp.file("rig.yaml")) << dis_rig(rx.port(), "max_extrapolation_ms: 150"); }
    RigProcess rig(tmp.file("rig.yaml"));
    ASSERT_GT(rig.port, 0) << rig.b.output;
    ModbusClient mb(rig.port);
    const int dis_port = arm_start_dis(rig, mb);
    ASSERT_GT(dis_port, 0) << rig.b.output;
    BackgroundMirage fake = start_mirage(
        "fake-ins --scene " + tmp.file("yard.yaml") + " --trajectory " + tmp.file("circle.csv") +
        " --protocol dis --duration 10 --to udp://127.0.0.1:" + std::to_string(dis_port));
    const core::GpsTime t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
    ASSERT_FALSE(rig.b.wait_for(std::regex("pulse 0 at gps")).empty()) << rig.b.output;
    const std::size_t live_from = rx.count();
    ASSERT_TRUE(eventually([&] { return rx.count() > live_from + 1000; }, 8)) << rig.b.output;
    // Freeze: after the packets in flight, every point fits one pose of the circle.
    ASSERT_EQ(mb.write(fault_hr(0, 2), 1), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::size_t frozen_from = rx.count();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    const auto frozen = rx.since(frozen_from);
    // Stale, injected over the frozen pose: packets go on, without returns; one stale period
    // counted.
    ASSERT_EQ(mb.write(fault_hr(0, 5), 1), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::size_t stale_from = rx.count();
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const auto stale = rx.since(stale_from);
    const std::uint32_t stale_periods = mb.in32(sensor_in(0, 10));
    ASSERT_EQ(mb.write(0, 3), 1);
    EXPECT_EQ(rig.interrupt(), 0) << rig.b.output;
    (void)fake.finish();
    // The frozen stretch against the truth at the points' times, and against the best single
    // pose of the circle within the 1 s before the stretch.
    const Stats moving = check_points(frozen, truth, t0);
    velodyne::DecodedPacket first;
    ASSERT_EQ(velodyne::decode_data(frozen.front(), nullptr, first), velodyne::DecodeStatus::Ok);
    const std::int64_t hour = core::unix_ns_from_gps(t0) / 3'600'000'000'000 * 3'600'000'000'000;
    core::GpsTime t_first = core::gps_from_unix_ns(hour + std::int64_t(first.timestamp_us) * 1000);
    if (t_first < t0) t_first += std::chrono::hours(1);
    std::vector<std::vector<std::uint8_t>> sample;  // every 5th packet keeps the search short
    for (std::size_t i = 0; i < frozen.size(); i += 5) sample.push_back(frozen[i]);
    double best = 1e9, best_dt = 0;
    for (int ms = 0; ms <= 1000; ms += 5) {
        const core::GpsTime t = t_first - std::chrono::milliseconds(ms);
        const double e = median_with_pose(sample, truth.at(truth.begin() + (t - t0)));
        if (e >= 0 && e < best) {
            best = e;
            best_dt = ms * 1e-3;
        }
    }
    std::size_t ok = 0, returns = 0;
    velodyne::DecodedPacket dp;
    for (const auto& p : stale)
        if (velodyne::decode_data(p, nullptr, dp) == velodyne::DecodeStatus::Ok) {
            ++ok;
            for (const auto& f : dp.firing) returns += f.distance_m > 0;
        }
    std::printf(
        "[ rig freeze ] %zu frozen packets: median %.4f m against the truth at their "
        "times, %.4f m against one pose %.3f s before the first; stale: %zu packets, %zu "
        "returns, %u stale periods\n",
        frozen.size(), moving.median, best, best_dt, ok, returns, stale_periods);
    EXPECT_GT(frozen.size(), 900u);
    EXPECT_GT(moving.median, 0.3);
    EXPECT_LT(best, 0.05);
    EXPECT_GT(ok, 400u);
    EXPECT_EQ(returns, 0u);
    EXPECT_EQ(stale_periods, 1u);
}

}  // namespace
}  // namespace mirage::test
