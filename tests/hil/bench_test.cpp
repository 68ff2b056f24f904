// SPDX-License-Identifier: Apache-2.0
// The benchmark's short run (ctest label `bench`): it completes and reports real figures.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cli_run.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

double json_number(const std::string& js, const std::string& key) {
    const auto p = js.find("\"" + key + "\":");
    if (p == std::string::npos) return -1;
    return std::stod(js.substr(p + key.size() + 3));
}

TEST(Bench, quick_run_reports_pipeline_ceiling_and_error_figures) {
    TempDir tmp;
    const auto r = run_mirage("bench --quick --repeat 2 --out-dir " + tmp.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream f(tmp.file("report.json"));
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string js = ss.str();
    EXPECT_GT(json_number(js, "bvh_build_seconds"), 0.0);
    EXPECT_GT(json_number(js, "bvh_bytes_per_triangle"), 1.0);
    EXPECT_GT(json_number(js, "las_points_per_s"), 1e5);
    EXPECT_GT(json_number(js, "pipeline_pulses_per_s"), 1e4);
    EXPECT_GT(json_number(js, "ceiling_pulses_per_s"), 1e4);
    const double ratio = json_number(js, "ratio");
    EXPECT_GT(ratio, 0.0);
    EXPECT_LT(ratio, 1.5);
    // Two alternating pipeline/ceiling pairs per row, the ratio of each pair reported.
    EXPECT_EQ(json_number(js, "repeats"), 2.0);
    const double lo = json_number(js, "ratio_min"), hi = json_number(js, "ratio_max");
    EXPECT_GT(lo, 0.0);
    EXPECT_LE(lo, hi);
    EXPECT_LT(hi, 1.5);
    EXPECT_GE(json_number(js, "range_rms_m"), 0.0);
    std::ifstream svg(tmp.file("time_vs_error.svg"));
    EXPECT_TRUE(svg.good());
    std::ifstream md(tmp.file("report.md"));
    EXPECT_TRUE(md.good());
    std::printf("%s\n", r.output.c_str());
}

}  // namespace
}  // namespace mirage::test
