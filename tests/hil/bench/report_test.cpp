// SPDX-License-Identifier: Apache-2.0
// `mirage bench` report files: a figure that is NaN or infinite reaches none of them (null in the
// JSON, n/a in the markdown, left out of the plot), and the JSON is valid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "bench_report.hpp"
#include "report_json.hpp"
#include "stream_report.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

hil::BenchReport report_with_nan() {
    hil::BenchReport r;
    r.machine = "test machine";
    r.scene_seconds = 0.1;
    r.bvh_build_seconds = kNaN;
    hil::ThroughputRow t;
    t.sensor = "vlp16";
    t.pipeline_pulses_per_s = kNaN;  // and so the ratio
    t.ceiling_pulses_per_s = 1e6;
    t.ratio_min = kInf;
    t.ratio_max = 0.5;
    r.throughput.push_back(t);
    r.las_points_per_s = kInf;
    hil::ErrorRow e;
    e.seconds = 0.2;
    e.range_rms_m = kNaN;  // not plotted
    e.intensity_rms = -kInf;
    r.errors.push_back(e);
    hil::ErrorRow fine;
    fine.sub_rays = 19;
    fine.seconds = 0.3;
    fine.range_rms_m = 0.01;
    r.errors.push_back(fine);
    hil::BvhRow b;
    b.quality = "medium";
    b.render_seconds = kNaN;
    r.bvh.push_back(b);
    return r;
}

TEST(BenchReport, nan_and_inf_never_reach_a_report_file) {
    TempDir tmp;
    hil::write_reports(report_with_nan(), tmp.path().string());
    for (const char* f : {"report.json", "report.md", "time_vs_error.svg"}) {
        const std::string text = lower(read_text(tmp.file(f)));
        ASSERT_FALSE(text.empty()) << f;
        EXPECT_EQ(text.find("nan"), std::string::npos) << f;
        EXPECT_EQ(text.find("inf"), std::string::npos) << f;
    }
    const auto js = nlohmann::json::parse(read_text(tmp.file("report.json")));
    EXPECT_TRUE(js.at("bvh_build_seconds").is_null());
    EXPECT_TRUE(js.at("las_points_per_s").is_null());
    EXPECT_DOUBLE_EQ(js.at("scene_seconds").get<double>(), 0.1);
    const auto& t = js.at("throughput").at(0);
    EXPECT_TRUE(t.at("pipeline_pulses_per_s").is_null());
    EXPECT_TRUE(t.at("ratio").is_null());
    EXPECT_TRUE(t.at("ratio_min").is_null());
    EXPECT_DOUBLE_EQ(t.at("ratio_max").get<double>(), 0.5);
    EXPECT_TRUE(js.at("time_vs_error").at(0).at("range_rms_m").is_null());
    EXPECT_TRUE(js.at("time_vs_error").at(0).at("intensity_rms").is_null());
    EXPECT_DOUBLE_EQ(js.at("time_vs_error").at(1).at("range_rms_m").get<double>(), 0.01);
    EXPECT_TRUE(js.at("bvh_quality").at(0).at("render_seconds").is_null());
    EXPECT_NE(read_text(tmp.file("report.md")).find("n/a"), std::string::npos);
    // The finite error row is plotted, the NaN one is not.
    const std::string svg = read_text(tmp.file("time_vs_error.svg"));
    EXPECT_NE(svg.find("19 rays"), std::string::npos);
    std::size_t circles = 0;
    for (auto p = svg.find("<circle"); p != std::string::npos; p = svg.find("<circle", p + 1))
        ++circles;
    EXPECT_EQ(circles, 1u);
}

// `mirage bench` fails on these rows: a pipeline faster than its own ceiling beyond noise.
TEST(BenchReport, rows_above_the_ceiling_are_those_over_the_tolerance) {
    hil::BenchReport r;
    for (double pipeline : {0.5, 1.1, 1.11, 2.0, kNaN}) {
        hil::ThroughputRow t;
        t.sensor = std::to_string(pipeline);
        t.pipeline_pulses_per_s = pipeline;
        t.ceiling_pulses_per_s = 1.0;
        r.throughput.push_back(t);
    }
    const auto above = hil::rows_above_ceiling(r);
    ASSERT_EQ(above.size(), 3u);
    EXPECT_DOUBLE_EQ(above[0].ratio(), 1.11);
    EXPECT_DOUBLE_EQ(above[1].ratio(), 2.0);
    EXPECT_TRUE(std::isnan(above[2].ratio()));
}

// The stream-bench report: the same for streams.md and streams.json.
TEST(StreamReport, nan_and_inf_never_reach_the_report) {
    hil::Report r;
    r.seconds = "3";
    hil::EncoderRow e;
    e.label = "VLP-16 strongest";
    e.seconds = kInf;
    e.packets_per_s = kNaN;
    r.encoder.push_back(e);
    hil::StreamRow t;
    t.label = "VLP-16 strongest";
    t.rate_error = kNaN;
    t.rx_packets_per_s = kInf;
    t.device_packets_per_s = 754.0;
    r.streams.rows.push_back(t);
    r.streams.wall_s = 3.0;
    r.streams.sender_cpu_s = kNaN;
    const std::string md = hil::stream_markdown(r), js = hil::stream_json(r);
    for (const std::string& text : {lower(md), lower(js)}) {
        EXPECT_EQ(text.find("nan"), std::string::npos) << text;
        EXPECT_EQ(text.find("inf"), std::string::npos) << text;
    }
    EXPECT_NE(md.find("n/a"), std::string::npos);
    const auto j = nlohmann::json::parse(js);
    EXPECT_EQ(j.at("seconds").get<double>(), 3.0);
    EXPECT_TRUE(j.at("encoder").at(0).at("encode_seconds").is_null());
    EXPECT_TRUE(j.at("encoder").at(0).at("packets_per_s").is_null());
    const auto& row = j.at("streams").at(0);
    EXPECT_TRUE(row.at("rate_error").is_null());
    EXPECT_TRUE(row.at("received_packets_per_s").is_null());
    EXPECT_EQ(row.at("device_packets_per_s").get<double>(), 754.0);
    EXPECT_TRUE(j.at("streams_run").at("sender_cpu_seconds").is_null());
}

}  // namespace
}  // namespace mirage::test
