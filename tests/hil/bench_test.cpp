// SPDX-License-Identifier: Apache-2.0
// The benchmark's short run (ctest label `bench`): it completes and its figures hold what they
// should: the pipeline never beats its own Embree ceiling beyond noise, rates are positive, the
// error falls as sub-rays grow, the reference converged, the BVH rows were measured.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

#include "cli_run.hpp"
#include "report_json.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using nlohmann::json;

void check_build_and_las(const json& r) {
    EXPECT_GT(measured(r, "bvh_build_seconds"), 0.0);
    EXPECT_GT(measured(r, "bvh_bytes_per_triangle"), 1.0);
    EXPECT_GT(measured(r, "las_points_per_s"), 1e5);
    EXPECT_GT(measured(r, "las_mb_per_s"), 0.0);
}

// Three sensors at 1 and 7 sub-rays (--quick), two alternating pipeline/ceiling pairs each; the
// best pipeline over the best ceiling within (0, 1.1].
void check_throughput(const json& r) {
    const json& rows = r.at("throughput");
    ASSERT_EQ(rows.size(), 6u);
    for (const json& t : rows) {
        const std::string row = t.at("sensor").get<std::string>() + " " + t.at("sub_rays").dump();
        EXPECT_GT(measured(t, "pipeline_pulses_per_s"), 1e4) << row;
        EXPECT_GT(measured(t, "pipeline_points_per_s"), 0.0) << row;
        EXPECT_GT(measured(t, "ceiling_pulses_per_s"), 1e4) << row;
        EXPECT_GE(measured(t, "ceiling_rays_per_s"), measured(t, "ceiling_pulses_per_s")) << row;
        const double ratio = measured(t, "ratio");
        EXPECT_GT(ratio, 0.0) << row;
        EXPECT_LE(ratio, 1.1) << row;
        EXPECT_EQ(t.at("repeats").get<int>(), 2) << row;
        const double lo = measured(t, "ratio_min"), hi = measured(t, "ratio_max");
        EXPECT_GT(lo, 0.0) << row;
        EXPECT_LE(lo, hi) << row;
        EXPECT_GT(t.at("points").get<std::uint64_t>(), 0u) << row;
    }
}

// Noise off, so the errors are exact: from 7 to 19 sub-rays the range and intensity errors
// against 37 fall, and 37 against 61 lies below 19 against 37 (the reference converged).
// Per detector: 1, 7, 19 against 37 and 37 against 61; range errors fall as sub-rays grow, and
// so do the discrete detector's intensity errors; the reference's own error is below the
// 1-sub-ray row's.
void check_errors(const json& r) {
    std::map<std::tuple<std::string, int, int>, json> rows;
    std::map<std::string, json> adaptive;
    for (const json& e : r.at("time_vs_error")) {
        if (e.at("footprint").get<std::string>() == "adaptive") {
            adaptive[e.at("detector").get<std::string>()] = e;
            continue;
        }
        rows[{e.at("detector").get<std::string>(), e.at("sub_rays").get<int>(),
              e.at("reference_sub_rays").get<int>()}] = e;
    }
    ASSERT_EQ(rows.size(), 8u);
    for (const std::string d : {"discrete", "waveform"}) {
        for (const auto& [s, ref] : {std::pair{1, 37}, {7, 37}, {19, 37}, {37, 61}}) {
            ASSERT_TRUE(rows.count({d, s, ref})) << d << " " << s << " against " << ref;
            const json& e = rows.at({d, s, ref});
            EXPECT_GT(measured(e, "seconds"), 0.0) << d << " " << s;
            EXPECT_GT(measured(e, "range_rms_m"), 0.0) << d << " " << s;
            EXPECT_GT(measured(e, "intensity_rms"), 0.0) << d << " " << s;
            EXPECT_LT(measured(e, "presence_mismatch"), 0.05) << d << " " << s;
        }
        const json &e7 = rows.at({d, 7, 37}), &e19 = rows.at({d, 19, 37}),
                   &e37 = rows.at({d, 37, 61});
        EXPECT_LT(measured(e19, "range_rms_m"), measured(e7, "range_rms_m")) << d;
        EXPECT_LT(measured(e37, "range_rms_m"), measured(e19, "range_rms_m")) << d;
        EXPECT_LT(measured(e37, "intensity_rms"), measured(rows.at({d, 1, 37}), "intensity_rms"))
            << d;
        // The adaptive footprint keeps the sampled 19's errors within 10 % (docs/physics.md
        // §2.9); its time is reported, not asserted (one short run here).
        ASSERT_TRUE(adaptive.count(d)) << d;
        const json& a = adaptive.at(d);
        EXPECT_EQ(a.at("sub_rays").get<int>(), 19) << d;
        EXPECT_GT(measured(a, "seconds"), 0.0) << d;
        EXPECT_LT(measured(a, "range_rms_m"), 1.1 * measured(e19, "range_rms_m")) << d;
        EXPECT_LT(measured(a, "intensity_rms"), 1.1 * measured(e19, "intensity_rms")) << d;
        if (d == "waveform") continue;  // its intensity RMS: see docs/benchmarks.md §1
        EXPECT_LT(measured(e19, "intensity_rms"), measured(e7, "intensity_rms")) << d;
        EXPECT_LT(measured(e37, "intensity_rms"), measured(e19, "intensity_rms")) << d;
    }
}

void check_bvh(const json& r) {
    const json& rows = r.at("bvh_quality");
    ASSERT_EQ(rows.size(), 1u);  // --quick: medium only
    const json& b = rows.at(0);
    EXPECT_EQ(b.at("bvh").get<std::string>(), "medium");
    EXPECT_GT(measured(b, "build_seconds"), 0.0);
    EXPECT_GT(measured(b, "render_seconds"), 0.0);
    EXPECT_GT(b.at("bvh_bytes").get<std::uint64_t>(), 1'000'000u);
    EXPECT_GT(b.at("rays").get<std::uint64_t>(), 0u);
}

// The waveform rows: both sensors, every rate measured, the ceiling above the waveform run.
void check_detectors(const json& r) {
    const json& rows = r.at("waveform_detector");
    ASSERT_EQ(rows.size(), 2u);
    for (const json& d : rows) {
        EXPECT_EQ(d.at("sub_rays").get<int>(), 7);
        EXPECT_GT(measured(d, "discrete_pulses_per_s"), 0.0);
        EXPECT_GT(measured(d, "waveform_pulses_per_s"), 0.0);
        EXPECT_GT(measured(d, "waveform_to_discrete"), 0.0);
        EXPECT_LE(measured(d, "waveform_to_ceiling"), 1.1) << d.dump();
        EXPECT_GT(measured(d, "cfd_to_peak"), 0.0);
        // The decomposition fits what the peak timing finds: more work, never less.
        EXPECT_GT(measured(d, "decomposition_to_peak"), 0.0);
        EXPECT_LE(measured(d, "decomposition_to_peak"), 1.1) << d.dump();
    }
}

// The path-depth rows: both sensors at depths 1–3; depth 1 traces no continuation, the car's
// deeper ones some (its drive passes trees, whose crowns pass light on: the quick flight's strip
// may miss every tree), and no row beats the first-hit ceiling.
void check_paths(const json& r) {
    const json& rows = r.at("path_depth");
    ASSERT_EQ(rows.size(), 6u);
    for (const json& p : rows) {
        const int depth = p.at("depth").get<int>();
        EXPECT_GT(measured(p, "pulses_per_s"), 0.0);
        EXPECT_LE(measured(p, "to_ceiling"), 1.1) << p.dump();
        const double segments = p.at("segments_per_pulse").get<double>();
        if (depth == 1) {
            EXPECT_EQ(segments, 0.0) << p.dump();
        } else if (p.at("sensor").get<std::string>() == "vlp16") {
            EXPECT_GT(segments, 0.0) << p.dump();
        }
    }
}

// One run (a few seconds of rendering) for all checks; a missing key throws, failing the test.
TEST(Bench, quick_run_reports_figures_that_hold) {
    TempDir tmp;
    const auto r = run_mirage("bench --quick --repeat 2 --out-dir " + tmp.path().string());
    std::printf("%s\n", r.output.c_str());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const json report = json::parse(read_text(tmp.file("report.json")));
    check_build_and_las(report);
    check_throughput(report);
    check_errors(report);
    check_bvh(report);
    check_detectors(report);
    check_paths(report);
    EXPECT_NE(read_text(tmp.file("time_vs_error.svg")).find("<circle"), std::string::npos);
    EXPECT_NE(read_text(tmp.file("report.md")).find("| vlp16 | 7 |"), std::string::npos);
}

}  // namespace
}  // namespace mirage::test
