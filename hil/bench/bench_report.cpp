// SPDX-License-Identifier: Apache-2.0
#include "bench_report.hpp"

#include <embree3/rtcore_config.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "mirage/core/error.hpp"
#include "report_figure.hpp"

namespace mirage::hil {
namespace {

std::ofstream open_out(const std::string& path) {
    std::ofstream f(path);
    if (!f) throw IoError(fmt::format("bench: cannot write '{}'", path));
    return f;
}

double per_triangle(const BenchReport& r) {
    return double(r.bvh_bytes) / double(std::max<std::uint64_t>(1, r.unique_triangles));
}

void markdown_throughput(std::ostream& md, const BenchReport& r) {
    const int repeats = r.throughput.empty() ? 1 : r.throughput.front().repeats;
    md << "## Pipeline against the Embree ceiling (same rays, same batches, same threads)\n\n";
    md << fmt::format(
        "The ceiling traces the pipeline's own ray batches on its thread layout and times only "
        "the Embree calls. Pipeline and ceiling alternate, {} time(s) each per row; the rates are "
        "the best of each (the runs least disturbed by other load), the last column the range of "
        "the ratio within each pair.\n\n",
        repeats);
    md << "| sensor | sub-rays | pulses | pipeline M pulses/s | M points/s | ceiling M "
          "pulses/s | ceiling M rays/s | ratio | × real time | ratio per pair |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
    for (const auto& t : r.throughput)
        md << fmt::format(
            "| {} | {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.2f} | {:.2f} | {:.1f} | {:.2f}–{:.2f} "
            "|\n",
            t.sensor, t.sub_rays, t.pulses, fig(t.pipeline_pulses_per_s / 1e6),
            fig(t.pipeline_points_per_s / 1e6), fig(t.ceiling_pulses_per_s / 1e6),
            fig(t.ceiling_rays_per_s / 1e6), fig(t.ratio()), fig(t.x_real_time()), fig(t.ratio_min),
            fig(t.ratio_max));
}

void markdown_detectors(std::ostream& md, const BenchReport& r) {
    if (r.detectors.empty()) return;
    md << "\n## Waveform detector against the discrete one (same rays, same run)\n\n"
          "The same job with `detector.type: linear` (1 GS/s digitiser, noise on) and with the "
          "discrete detector, and the Embree ceiling of those rays, interleaved; the best run of "
          "each (docs/time-resolved.md §12). The waveform detector times echoes by their peak; the "
          "last two columns time them by constant fraction and by Gaussian decomposition "
          "(§12.1), relative to the peak timing.\n\n"
          "| sensor | sub-rays | pulses | discrete M pulses/s | waveform M pulses/s | waveform / "
          "discrete | ceiling M pulses/s | waveform / ceiling | waveform M points/s | constant "
          "fraction / peak | decomposition / peak |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& d : r.detectors)
        md << fmt::format(
            "| {} | {} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | "
            "{:.2f} |\n",
            d.sensor, d.sub_rays, d.pulses, fig(d.discrete_pulses_per_s / 1e6),
            fig(d.waveform_pulses_per_s / 1e6), fig(d.to_discrete()),
            fig(d.ceiling_pulses_per_s / 1e6), fig(d.to_ceiling()),
            fig(d.waveform_points_per_s / 1e6), fig(d.cfd_to_peak()),
            fig(d.decomposition_to_peak()));
}

void markdown_photon(std::ostream& md, const BenchReport& r) {
    if (r.photon.empty()) return;
    md << "\n## Photon counting (Geiger-mode arrays, same rays, same run)\n\n"
          "The Geiger-mode pipeline (one pixel-pulse per pixel and laser pulse, events to a LAS "
          "sink on /dev/null) and the Embree ceiling of its rays, interleaved, the best of each; "
          "real time is the sensor's own pixel-pulse rate; the coincidence processor's time is "
          "for the whole collection against its duration (docs/photon-counting.md §7).\n\n"
          "| sensor | trajectory | pixel-pulses | M pixel-pulses/s | M events/s | ceiling M "
          "pixel-pulses/s | pipeline / ceiling | x real time | coincidence s | coincidence x real "
          "time | points |\n"
          "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& p : r.photon)
        md << fmt::format(
            "| {} | {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.2f} | {:.3f} | {:.3f} | {:.2f} | {} "
            "|\n",
            p.sensor, p.trajectory, p.pulses, fig(p.pulses_per_s / 1e6), fig(p.points_per_s / 1e6),
            fig(p.ceiling_pulses_per_s / 1e6), fig(p.to_ceiling()), fig(p.x_real_time()),
            fig(p.coincidence_seconds), fig(p.coincidence_x_real_time()), p.coincidence_points);
}

void markdown_paths(std::ostream& md, const BenchReport& r) {
    if (r.paths.empty()) return;
    md << "\n## Path depth (same rays, same run)\n\n"
          "The same job with `receiver.max_path_depth` 1 (first hits only), 2 and 3 on the demo "
          "town, whose tree crowns pass light on and whose first building has a glass front, and "
          "the Embree ceiling of the first-hit rays, interleaved; the best run of each "
          "(docs/time-resolved.md §5).\n\n"
          "| sensor | sub-rays | depth | pulses | M pulses/s | / depth 1 | / ceiling | segments "
          "per pulse | M points/s |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& p : r.paths)
        md << fmt::format("| {} | {} | {} | {} | {:.3f} | {:.2f} | {:.2f} | {:.4f} | {:.3f} |\n",
                          p.sensor, p.sub_rays, p.depth, p.pulses, fig(p.pulses_per_s / 1e6),
                          fig(p.to_first_hit()), fig(p.to_ceiling()), fig(p.segments_per_pulse),
                          fig(p.points_per_s / 1e6));
}

void markdown_errors(std::ostream& md, const BenchReport& r) {
    md << "## Run time against error (VLP-16, demo drive, noise off)\n\n"
          "Each render against a denser reference of the same detector (37 sub-rays); the last "
          "row of each detector is that reference against 61 sub-rays, its own error. The "
          "waveform rows use the linear detector (1 GS/s, peak timing) noise-free. An adaptive "
          "footprint traces 7 probes per pulse and the rest only where they disagree; its time "
          "and the sampled 19's are each the best of three alternating runs.\n\n"
          "| detector | footprint | sub-rays | reference | time s | range RMS mm | range p50 mm | "
          "range p95 "
          "mm | on another surface % | range RMS on the same surface mm | intensity RMS | "
          "return presence differs % |\n"
          "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& e : r.errors)
        md << fmt::format(
            "| {} | {} | {} | {} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | {:.3f} | {:.2f} | {:.1f} | "
            "{:.3f} |\n",
            e.detector, e.footprint, e.sub_rays, e.reference_sub_rays, fig(e.seconds),
            fig(e.range_rms_m * 1000.0), fig(e.range_p50_m * 1000.0), fig(e.range_p95_m * 1000.0),
            fig(100.0 * e.other_surface), fig(e.same_surface_range_rms_m * 1000.0),
            fig(e.intensity_rms), fig(100.0 * e.presence_mismatch));
    for (const auto& e : r.errors)
        if (e.reference_sub_rays == 37 && e.sub_rays == 1)
            md << fmt::format("\nReference render time ({}): {:.3f} s.\n", e.detector,
                              fig(e.reference_seconds));
}

double rays_per_s(const BvhRow& b) {
    return b.render_seconds > 0 ? double(b.rays) / b.render_seconds : 0.0;
}

void markdown_bvh(std::ostream& md, const BenchReport& r) {
    if (r.bvh.empty()) return;
    md << "\n## BVH quality (same job; the quality changes no hit, only build and trace time)\n\n"
          "| BVH | build s | MB | sub-rays | render s | M rays/s |\n"
          "|---|---:|---:|---:|---:|---:|\n";
    for (const auto& b : r.bvh)
        md << fmt::format("| {} | {:.3f} | {:.1f} | {} | {:.3f} | {:.1f} |\n", b.quality,
                          fig(b.build_seconds), fig(double(b.bvh_bytes) / 1e6), b.sub_rays,
                          fig(b.render_seconds), fig(rays_per_s(b) / 1e6));
}

void write_markdown(const BenchReport& r, const std::string& path) {
    auto md = open_out(path);
    md << "# mirage bench\n\nMachine: " << r.machine << "\n\n";
    md << fmt::format(
        "Demo town: {} placed triangles ({} stored), generated in {:.2f} s; BVH (MEDIUM) built in "
        "{:.3f} s, {:.1f} MB = {:.1f} bytes per stored triangle.\n\n",
        r.triangles_placed, r.unique_triangles, fig(r.scene_seconds), fig(r.bvh_build_seconds),
        fig(double(r.bvh_bytes) / 1e6), fig(per_triangle(r)));
    markdown_throughput(md, r);
    markdown_detectors(md, r);
    markdown_paths(md, r);
    markdown_photon(md, r);
    md << fmt::format(
        "\nLAS write (point format 6, to a file): {:.2f} M points/s, {:.0f} MB/s ({} points).\n\n",
        fig(r.las_points_per_s / 1e6), fig(r.las_mb_per_s), r.las_points);
    markdown_errors(md, r);
    markdown_bvh(md, r);
}

nlohmann::ordered_json throughput_json(const ThroughputRow& t) {
    return {{"sensor", t.sensor},
            {"sub_rays", t.sub_rays},
            {"pulses", t.pulses},
            {"points", t.points},
            {"pipeline_pulses_per_s", t.pipeline_pulses_per_s},
            {"pipeline_points_per_s", t.pipeline_points_per_s},
            {"ceiling_pulses_per_s", t.ceiling_pulses_per_s},
            {"ceiling_rays_per_s", t.ceiling_rays_per_s},
            {"ratio", t.ratio()},
            {"x_real_time", t.x_real_time()},
            {"repeats", t.repeats},
            {"ratio_min", t.ratio_min},
            {"ratio_max", t.ratio_max}};
}

nlohmann::ordered_json detector_json(const DetectorRow& d) {
    return {{"sensor", d.sensor},
            {"sub_rays", d.sub_rays},
            {"pulses", d.pulses},
            {"repeats", d.repeats},
            {"discrete_pulses_per_s", d.discrete_pulses_per_s},
            {"waveform_pulses_per_s", d.waveform_pulses_per_s},
            {"ceiling_pulses_per_s", d.ceiling_pulses_per_s},
            {"waveform_to_discrete", d.to_discrete()},
            {"waveform_to_ceiling", d.to_ceiling()},
            {"cfd_pulses_per_s", d.cfd_pulses_per_s},
            {"decomposition_pulses_per_s", d.decomposition_pulses_per_s},
            {"cfd_to_peak", d.cfd_to_peak()},
            {"decomposition_to_peak", d.decomposition_to_peak()}};
}

nlohmann::ordered_json photon_json(const PhotonRow& p) {
    return {{"sensor", p.sensor},
            {"trajectory", p.trajectory},
            {"pixel_pulses", p.pulses},
            {"events", p.points},
            {"repeats", p.repeats},
            {"pixel_pulses_per_s", p.pulses_per_s},
            {"events_per_s", p.points_per_s},
            {"ceiling_pixel_pulses_per_s", p.ceiling_pulses_per_s},
            {"pipeline_to_ceiling", p.to_ceiling()},
            {"x_real_time", p.x_real_time()},
            {"collection_seconds", p.collection_seconds},
            {"coincidence_seconds", p.coincidence_seconds},
            {"coincidence_x_real_time", p.coincidence_x_real_time()},
            {"coincidence_points", p.coincidence_points}};
}

nlohmann::ordered_json path_json(const PathRow& p) {
    return {{"sensor", p.sensor},
            {"sub_rays", p.sub_rays},
            {"depth", p.depth},
            {"pulses", p.pulses},
            {"repeats", p.repeats},
            {"pulses_per_s", p.pulses_per_s},
            {"ceiling_pulses_per_s", p.ceiling_pulses_per_s},
            {"to_first_hit", p.to_first_hit()},
            {"to_ceiling", p.to_ceiling()},
            {"segments_per_pulse", p.segments_per_pulse}};
}

nlohmann::ordered_json error_json(const ErrorRow& e) {
    return {{"detector", e.detector},
            {"footprint", e.footprint},
            {"sub_rays", e.sub_rays},
            {"reference_sub_rays", e.reference_sub_rays},
            {"seconds", e.seconds},
            {"reference_seconds", e.reference_seconds},
            {"range_rms_m", e.range_rms_m},
            {"range_p50_m", e.range_p50_m},
            {"range_p95_m", e.range_p95_m},
            {"other_surface", e.other_surface},
            {"same_surface_range_rms_m", e.same_surface_range_rms_m},
            {"intensity_rms", e.intensity_rms},
            {"presence_mismatch", e.presence_mismatch}};
}

nlohmann::ordered_json bvh_json(const BvhRow& b) {
    return {
        {"bvh", b.quality},       {"build_seconds", b.build_seconds},   {"bvh_bytes", b.bvh_bytes},
        {"sub_rays", b.sub_rays}, {"render_seconds", b.render_seconds}, {"rays", b.rays}};
}

}  // namespace

// nlohmann-json serialises a NaN or infinite number as null (serializer::dump_float), so a
// figure that could not be measured reads null, never NaN.
std::string report_json(const BenchReport& r) {
    nlohmann::ordered_json j = {{"machine", r.machine},
                                {"scene_seconds", r.scene_seconds},
                                {"bvh_build_seconds", r.bvh_build_seconds},
                                {"bvh_bytes", r.bvh_bytes},
                                {"triangles_placed", r.triangles_placed},
                                {"triangles_stored", r.unique_triangles},
                                {"bvh_bytes_per_triangle", per_triangle(r)},
                                {"las_points", r.las_points},
                                {"las_points_per_s", r.las_points_per_s},
                                {"las_mb_per_s", r.las_mb_per_s},
                                {"throughput", nlohmann::ordered_json::array()},
                                {"waveform_detector", nlohmann::ordered_json::array()},
                                {"path_depth", nlohmann::ordered_json::array()},
                                {"photon_counting", nlohmann::ordered_json::array()},
                                {"time_vs_error", nlohmann::ordered_json::array()},
                                {"bvh_quality", nlohmann::ordered_json::array()}};
    for (const auto& t : r.throughput) j["throughput"].push_back(throughput_json(t));
    for (const auto& d : r.detectors) j["waveform_detector"].push_back(detector_json(d));
    for (const auto& p : r.paths) j["path_depth"].push_back(path_json(p));
    for (const auto& p : r.photon) j["photon_counting"].push_back(photon_json(p));
    for (const auto& e : r.errors) j["time_vs_error"].push_back(error_json(e));
    for (const auto& b : r.bvh) j["bvh_quality"].push_back(bvh_json(b));
    return j.dump(2) + "\n";
}

std::vector<ThroughputRow> rows_above_ceiling(const BenchReport& r) {
    std::vector<ThroughputRow> out;
    for (const auto& t : r.throughput)
        if (!(t.ratio() <= kCeilingTolerance)) out.push_back(t);  // NaN too
    return out;
}

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

namespace {

// A point of the plot: rows whose time or error is not finite are left out.
bool plotted(const ErrorRow& e) { return std::isfinite(e.seconds) && std::isfinite(e.range_rms_m); }

// Scatter of run time (x) against range RMS (y, log, mm) of the error rows.
struct Plot {
    static constexpr double W = 640, H = 420, L = 70, B = 50, T = 30, R = 20;
    double tmax = 1e-6, lmin = 0, lmax = 1;
    explicit Plot(const std::vector<ErrorRow>& errors) {
        double emin = 1e9, emax = 1e-9;
        for (const auto& e : errors) {
            if (!plotted(e)) continue;
            tmax = std::max(tmax, e.seconds);
            const double v = std::max(1e-6, e.range_rms_m * 1000.0);
            emin = std::min(emin, v);
            emax = std::max(emax, v);
        }
        if (emin >= emax) emax = emin * 10;
        lmin = std::floor(std::log10(emin));
        lmax = std::ceil(std::log10(emax));
    }
    double x(double t) const { return L + (W - L - R) * t / (tmax * 1.1); }
    double y(double e) const {
        const double l = std::log10(std::max(1e-6, e));
        return T + (H - T - B) * (1.0 - (l - lmin) / std::max(1e-9, lmax - lmin));
    }
};

void svg_axes(std::ostream& svg, const Plot& p) {
    using P = Plot;
    svg << fmt::format(
        "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
        "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n",
        P::W, P::H);
    svg << fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black'/>\n", P::L,
                       P::H - P::B, P::W - P::R, P::H - P::B);
    svg << fmt::format("<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black'/>\n", P::L, P::T, P::L,
                       P::H - P::B);
    svg << fmt::format("<text x='{}' y='{}' text-anchor='middle'>run time, s</text>\n",
                       (P::L + P::W - P::R) / 2, P::H - 10);
    svg << fmt::format(
        "<text x='15' y='{}' transform='rotate(-90 15 {})' text-anchor='middle'>range RMS vs "
        "reference, mm (log)</text>\n",
        (P::T + P::H - P::B) / 2, (P::T + P::H - P::B) / 2);
    for (double l = p.lmin; l <= p.lmax; l += 1)
        svg << fmt::format("<text x='{}' y='{}' text-anchor='end'>{:g}</text>\n", P::L - 5,
                           p.y(std::pow(10, l)) + 4, std::pow(10, l));
    for (int i = 0; i <= 4; ++i)
        svg << fmt::format("<text x='{}' y='{}' text-anchor='middle'>{:.2f}</text>\n",
                           p.x(p.tmax * 1.1 * i / 4), P::H - P::B + 16, p.tmax * 1.1 * i / 4);
}

void write_svg(const BenchReport& r, const std::string& path) {
    auto svg = open_out(path);
    const Plot p(r.errors);
    svg_axes(svg, p);
    for (const auto& e : r.errors) {
        if (!plotted(e)) continue;
        // Against the 37-sub-ray reference: orange (discrete), green (waveform); the reference
        // against 61: purple, light purple.
        const bool wave = e.detector == "waveform";
        const char* col = e.reference_sub_rays > 37 ? (wave ? "#b3a7e0" : "#7570b3")
                                                    : (wave ? "#1b9e77" : "#d95f02");
        const double x = p.x(e.seconds), y = p.y(std::max(1e-6, e.range_rms_m * 1000.0));
        svg << fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='5' fill='{}'/>\n", x, y, col);
        svg << fmt::format("<text x='{:.1f}' y='{:.1f}'>{} rays{}</text>\n", x + 7, y - 4,
                           e.sub_rays, e.footprint == "adaptive" ? " adaptive" : "");
    }
    svg << fmt::format(
        "<text x='{}' y='18'>VLP-16 run time vs range error (against 37 sub-rays: orange "
        "discrete, green waveform; 37 against 61: purple)</text>\n</svg>\n",
        Plot::L);
}

}  // namespace

void write_reports(const BenchReport& r, const std::string& dir) {
    write_markdown(r, dir + "/report.md");
    auto js = open_out(dir + "/report.json");
    js << report_json(r);
    write_svg(r, dir + "/time_vs_error.svg");
}
}  // namespace mirage::hil
