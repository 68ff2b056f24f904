// SPDX-License-Identifier: Apache-2.0
// `mirage stream-bench --quick` (ctest label `bench`): it completes, every stream reaches the
// loopback receiver and every encoder outruns its device. No timing targets are asserted (the
// CI machine is shared); the figures are printed.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

// Every value of `"key": <number>` in document order (the report writes one object per line).
std::vector<double> json_numbers(const std::string& js, const std::string& key) {
    std::vector<double> out;
    const std::string needle = "\"" + key + "\": ";
    for (auto p = js.find(needle); p != std::string::npos; p = js.find(needle, p + 1))
        out.push_back(std::stod(js.substr(p + needle.size())));
    return out;
}

std::string read_all(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

TEST(StreamBench, quick_run_streams_three_sensors_and_encoders_outrun_devices) {
    TempDir tmp;
    const auto r = run_mirage("stream-bench --quick --out-dir " + tmp.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string js = read_all(tmp.file("streams.json"));
    ASSERT_FALSE(js.empty());

    // The three streams: VLP-16, HDL-64E S3 dual, OS1-128 2048x10.
    for (const char* name : {"VLP-16 strongest", "HDL-64E S3 dual", "OS1-128 2048x10 RNG19"})
        EXPECT_NE(js.find(std::string("{\"name\": \"") + name + "\", \"device_packets_per_s\""),
                  std::string::npos)
            << name;
    // The default: one shared sending thread for the three streams (issue 3 item 9).
    EXPECT_NE(js.find("\"sender\": \"shared\""), std::string::npos);
    const auto received = json_numbers(js, "received_data_packets");
    const auto sent = json_numbers(js, "sent_data_packets");
    const auto expected = json_numbers(js, "expected_data_packets");
    ASSERT_EQ(received.size(), 3u);
    ASSERT_EQ(sent.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_GT(received[i], 0.0) << "stream " << i;
        EXPECT_LE(received[i], sent[i]) << "stream " << i;
        // The pipeline renders exactly --seconds of pulses: whole packets of 3 s of the device.
        EXPECT_NEAR(sent[i], expected[i], 1.0 + 1e-3 * expected[i]) << "stream " << i;
    }
    // The shared sender times its send calls (a loopback send: microseconds, not seconds) and
    // its timed wake-ups.
    const auto send_p99 = json_numbers(js, "send_p99_us");
    ASSERT_EQ(send_p99.size(), 3u);
    for (double v : send_p99) {
        EXPECT_GT(v, 0.0);
        EXPECT_LT(v, 1e6);
    }
    const auto wake_p99 = json_numbers(js, "sender_wake_late_p99_us");
    ASSERT_EQ(wake_p99.size(), 1u);
    EXPECT_GT(wake_p99[0], 0.0);  // thousands of timed wake-ups in 3 s: a histogram with data
    EXPECT_LT(wake_p99[0], 1e6);
    // Closed-form device rates of the three streams (wire-formats.md): VLP-16 strongest
    // 1e9 / (24 × 55 296 ns), OS1-128 2048x10 = 2048 / 16 × 10.
    const auto device = json_numbers(js, "device_packets_per_s");
    ASSERT_EQ(device.size(), 8u + 3u);  // encoder rows, then stream rows
    EXPECT_NEAR(device[8], 1e9 / (24 * 55'296.0), 1e-2);
    EXPECT_NEAR(device[10], 1280.0, 1e-9);

    // Eight encoder rows, each faster than its device (encoding alone).
    const auto rate = json_numbers(js, "packets_per_s");
    const auto packets = json_numbers(js, "packets");
    ASSERT_GE(rate.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) {
        EXPECT_GT(packets[i], 0.0) << "encoder row " << i;
        EXPECT_GT(rate[i], device[i]) << "encoder row " << i;
    }
    // Pacing probe rows: the plain run always runs and gets its packets back.
    const auto probe_received = json_numbers(js, "received");
    ASSERT_GE(probe_received.size(), 1u);
    EXPECT_GT(probe_received[0], 0.0);
    EXPECT_FALSE(read_all(tmp.file("streams.md")).empty());
    std::printf("%s\n", r.output.c_str());
}

}  // namespace
}  // namespace mirage::test
