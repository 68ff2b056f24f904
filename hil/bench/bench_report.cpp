// SPDX-License-Identifier: Apache-2.0
#include "bench_report.hpp"

#include <embree3/rtcore_config.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <thread>

#include "mirage/core/error.hpp"

namespace mirage::hil {
namespace {

std::ofstream open_out(const std::string& path) {
    std::ofstream f(path);
    if (!f) throw IoError(fmt::format("bench: cannot write '{}'", path));
    return f;
}

}  // namespace

std::string cpu_model() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::string machine_description(int threads) {
    return fmt::format("{}, {} hardware threads, {} worker threads, Embree {}", cpu_model(),
                       std::thread::hardware_concurrency(), threads, RTC_VERSION_STRING);
}

void write_reports(const BenchReport& r, const std::string& dir) {
    const double bpt = double(r.bvh_bytes) / double(std::max<std::uint64_t>(1, r.unique_triangles));
    {
        auto md = open_out(dir + "/report.md");
        md << "# mirage bench\n\nMachine: " << r.machine << "\n\n";
        md << fmt::format(
            "Demo town: {} placed triangles ({} stored), generated in {:.2f} s; BVH (MEDIUM) built "
            "in "
            "{:.3f} s, {:.1f} MB = {:.1f} bytes per stored triangle.\n\n",
            r.triangles_placed, r.unique_triangles, r.scene_seconds, r.bvh_build_seconds,
            double(r.bvh_bytes) / 1e6, bpt);
        const int repeats = r.throughput.empty() ? 1 : r.throughput.front().repeats;
        md << "## Pipeline against the Embree ceiling (same rays, same threads)\n\n";
        md << fmt::format(
            "Pipeline and ceiling alternate, {} time(s) each per row; the rates are the best of "
            "each (the runs least disturbed by other load), the last column the range of the "
            "ratio within each pair.\n\n",
            repeats);
        md << "| sensor | sub-rays | pulses | pipeline M pulses/s | M points/s | ceiling M "
              "pulses/s | ceiling M rays/s | ratio | × real time | ratio per pair |\n"
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
        for (const auto& t : r.throughput)
            md << fmt::format(
                "| {} | {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.2f} | {:.2f} | {:.1f} | "
                "{:.2f}–{:.2f} |\n",
                t.sensor, t.sub_rays, t.pulses, t.pipeline_pulses_per_s / 1e6,
                t.pipeline_points_per_s / 1e6, t.ceiling_pulses_per_s / 1e6,
                t.ceiling_rays_per_s / 1e6, t.ratio(), t.x_real_time(), t.ratio_min, t.ratio_max);
        md << fmt::format(
            "\nLAS write (point format 6, to a file): {:.2f} M points/s, {:.0f} MB/s ({} "
            "points).\n\n",
            r.las_points_per_s / 1e6, r.las_mb_per_s, r.las_points);
        md << "## Run time against error (VLP-16, demo drive, noise off)\n\n"
              "Each render against a denser reference (37 sub-rays); the last row is that "
              "reference against 61 sub-rays, its own error.\n\n"
              "| sub-rays | reference | time s | range RMS mm | range p50 mm | range p95 mm | "
              "on another surface % | range RMS on the same surface mm | intensity RMS | "
              "return presence differs % |\n"
              "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const auto& e : r.errors)
            md << fmt::format(
                "| {} | {} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | {:.1f} | {:.3f} "
                "|\n",
                e.sub_rays, e.reference_sub_rays, e.seconds, e.range_rms_m * 1000.0,
                e.range_p50_m * 1000.0, e.range_p95_m * 1000.0, 100.0 * e.other_surface,
                e.same_surface_range_rms_m * 1000.0, e.intensity_rms, 100.0 * e.presence_mismatch);
        if (!r.errors.empty())
            md << fmt::format("\nReference render time: {:.3f} s.\n",
                              r.errors.front().reference_seconds);
        if (!r.bvh.empty()) {
            md << "\n## BVH quality (same job; the quality changes no hit, only build and trace "
                  "time)\n\n| BVH | build s | MB | sub-rays | render s | M rays/s |\n"
                  "|---|---:|---:|---:|---:|---:|\n";
            for (const auto& b : r.bvh)
                md << fmt::format(
                    "| {} | {:.3f} | {:.1f} | {} | {:.3f} | {:.1f} |\n", b.quality, b.build_seconds,
                    double(b.bvh_bytes) / 1e6, b.sub_rays, b.render_seconds,
                    b.render_seconds > 0 ? double(b.rays) / b.render_seconds / 1e6 : 0.0);
        }
    }
    {
        auto js = open_out(dir + "/report.json");
        js << "{\n" << fmt::format("  \"machine\": \"{}\",\n", r.machine);
        js << fmt::format(
            "  \"scene_seconds\": {}, \"bvh_build_seconds\": {}, \"bvh_bytes\": {},\n",
            r.scene_seconds, r.bvh_build_seconds, r.bvh_bytes);
        js << fmt::format(
            "  \"triangles_placed\": {}, \"triangles_stored\": {}, \"bvh_bytes_per_triangle\": "
            "{},\n",
            r.triangles_placed, r.unique_triangles, bpt);
        js << fmt::format("  \"las_points_per_s\": {}, \"las_mb_per_s\": {},\n", r.las_points_per_s,
                          r.las_mb_per_s);
        js << "  \"throughput\": [\n";
        for (std::size_t i = 0; i < r.throughput.size(); ++i) {
            const auto& t = r.throughput[i];
            js << fmt::format(
                "    {{\"sensor\": \"{}\", \"sub_rays\": {}, \"pulses\": {}, \"points\": {}, "
                "\"pipeline_pulses_per_s\": {}, \"pipeline_points_per_s\": {}, "
                "\"ceiling_pulses_per_s\": {}, "
                "\"ceiling_rays_per_s\": {}, \"ratio\": {}, \"x_real_time\": {}, "
                "\"repeats\": {}, \"ratio_min\": {}, \"ratio_max\": {}}}{}\n",
                t.sensor, t.sub_rays, t.pulses, t.points, t.pipeline_pulses_per_s,
                t.pipeline_points_per_s, t.ceiling_pulses_per_s, t.ceiling_rays_per_s, t.ratio(),
                t.x_real_time(), t.repeats, t.ratio_min, t.ratio_max,
                i + 1 < r.throughput.size() ? "," : "");
        }
        js << "  ],\n  \"time_vs_error\": [\n";
        for (std::size_t i = 0; i < r.errors.size(); ++i) {
            const auto& e = r.errors[i];
            js << fmt::format(
                "    {{\"sub_rays\": {}, \"reference_sub_rays\": {}, \"seconds\": {}, "
                "\"range_rms_m\": {}, \"range_p50_m\": {}, \"range_p95_m\": {}, "
                "\"other_surface\": {}, \"same_surface_range_rms_m\": {}, "
                "\"intensity_rms\": {}, \"presence_mismatch\": {}}}{}\n",
                e.sub_rays, e.reference_sub_rays, e.seconds, e.range_rms_m, e.range_p50_m,
                e.range_p95_m, e.other_surface, e.same_surface_range_rms_m, e.intensity_rms,
                e.presence_mismatch, i + 1 < r.errors.size() ? "," : "");
        }
        js << "  ],\n  \"bvh_quality\": [\n";
        for (std::size_t i = 0; i < r.bvh.size(); ++i) {
            const auto& b = r.bvh[i];
            js << fmt::format(
                "    {{\"bvh\": \"{}\", \"build_seconds\": {}, \"bvh_bytes\": {}, "
                "\"sub_rays\": {}, \"render_seconds\": {}, \"rays\": {}}}{}\n",
                b.quality, b.build_seconds, b.bvh_bytes, b.sub_rays, b.render_seconds, b.rays,
                i + 1 < r.bvh.size() ? "," : "");
        }
        js << "  ]\n}\n";
    }
    {
        // Scatter of run time (x) against range RMS (y, log) per setting.
        auto svg = open_out(dir + "/time_vs_error.svg");
        const double W = 640, H = 420, L = 70, B = 50, T = 30, R = 20;
        double tmax = 1e-6, emin = 1e9, emax = 1e-9;
        for (const auto& e : r.errors) {
            tmax = std::max(tmax, e.seconds);
            const double v = std::max(1e-6, e.range_rms_m * 1000.0);
            emin = std::min(emin, v);
            emax = std::max(emax, v);
        }
        if (emin >= emax) emax = emin * 10;
        const double lmin = std::floor(std::log10(emin)), lmax = std::ceil(std::log10(emax));
        auto X = [&](double t) { return L + (W - L - R) * t / (tmax * 1.1); };
        auto Y = [&](double e) {
            const double l = std::log10(std::max(1e-6, e));
            return T + (H - T - B) * (1.0 - (l - lmin) / std::max(1e-9, lmax - lmin));
        };
        svg << fmt::format(
            "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' "
            "font-family='sans-serif' "
            "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n",
            W, H);
        svg << fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black'/>\n", L, H - B,
                           W - R, H - B);
        svg << fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black'/>\n", L, T, L,
                           H - B);
        svg << fmt::format("<text x='{}' y='{}' text-anchor='middle'>run time, s</text>\n",
                           (L + W - R) / 2, H - 10);
        svg << fmt::format(
            "<text x='15' y='{}' transform='rotate(-90 15 {})' text-anchor='middle'>range RMS vs "
            "reference, mm (log)</text>\n",
            (T + H - B) / 2, (T + H - B) / 2);
        for (double l = lmin; l <= lmax; l += 1)
            svg << fmt::format("<text x='{}' y='{}' text-anchor='end'>{:g}</text>\n", L - 5,
                               Y(std::pow(10, l)) + 4, std::pow(10, l));
        for (int i = 0; i <= 4; ++i)
            svg << fmt::format("<text x='{}' y='{}' text-anchor='middle'>{:.2f}</text>\n",
                               X(tmax * 1.1 * i / 4), H - B + 16, tmax * 1.1 * i / 4);
        for (const auto& e : r.errors) {
            // Orange: against the 37-sub-ray reference; purple: the reference against 61.
            const char* col = e.reference_sub_rays > 37 ? "#7570b3" : "#d95f02";
            const double x = X(e.seconds), y = Y(std::max(1e-6, e.range_rms_m * 1000.0));
            svg << fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='5' fill='{}'/>\n", x, y, col);
            svg << fmt::format("<text x='{:.1f}' y='{:.1f}'>{} rays</text>\n", x + 7, y - 4,
                               e.sub_rays);
        }
        svg << fmt::format(
            "<text x='{}' y='18'>VLP-16 run time vs range error (orange: against 37 sub-rays, "
            "purple: 37 against 61)</text>\n</svg>\n",
            L);
    }
}

}  // namespace mirage::hil
