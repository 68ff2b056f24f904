// SPDX-License-Identifier: Apache-2.0
// No documented key does nothing: every scene-file and sensor-file key the docs list is changed,
// one at a time, in a context where it should matter, and `mirage render` must then write a
// different LAS file (or, for labels, print a different summary) — or refuse the key. The list is
// checked against docs/file-formats.md and docs/sensors.md, so a key documented there without a
// case here fails too.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "test_paths.hpp"

// g++ 12 reports -Warray-bounds and -Wstringop-overflow falsely in std::string's concatenation of a
// literal and a temporary once cases() holds this many strings (GCC bug 105651): the strings are
// ordinary.
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wstringop-overflow"

namespace mirage::test {
namespace {

enum class Expect { LasDiffers, TextDiffers, Refused };

// Two configurations that differ in one key. Empty scene/sensor texts take the defaults below.
struct KeyCase {
    std::string key;  // as the docs write it
    std::string scene_a = {}, scene_b = {}, sensor_a = {}, sensor_b = {};
    std::string args = {};  // extra `mirage render` options for both runs
    Expect expect = Expect::LasDiffers;
};

// A plane with a box on it, seen by a sensor 1.5 m above the plane.
std::string scene(const std::string& object, const std::string& material = "{reflectance: 0.5}",
                  const std::string& extra = "") {
    return extra + "materials:\n  m: " + material +
           "\n  m2: {reflectance: 0.2}\nobjects:\n  - {type: plane, material: m, size: [80, 80]}\n"
           "  - " +
           object + "\n";
}
const std::string kBox =
    "{type: box, material: m, size: [3, 3, 3], transform: {translate: [8, 0, 1.5]}}";
std::string box_with(const std::string& keys) {
    return "{type: box, material: m, size: [3, 3, 3], " + keys + "}";
}
std::string box_at(const std::string& transform) {
    return "{type: box, material: m, size: [3, 3, 3], transform: {translate: [8, 0, 1.5], " +
           transform + "}}";
}
std::string ground(const std::string& keys) {
    return "{type: heightfield, material: m2, " + keys + "}";
}
std::string material(const std::string& keys) { return scene(kBox, "{" + keys + "}"); }
// The box in its own material `g` on the plane.
std::string glass_box(const std::string& keys) {
    return "materials:\n  m: {reflectance: 0.5}\n  g: {" + keys +
           "}\nobjects:\n  - {type: plane, material: m, size: [80, 80]}\n"
           "  - {type: box, material: g, size: [3, 3, 3], transform: {translate: [8, 0, 1.5]}}\n";
}

const std::string kVlp16 = "base: vlp16\n";
const std::string kAls = "base: als-mirror\n";
// Returns so weak that the sunlit background decides which are voids.
const std::string kWeak = "base: vlp16\nbeam:\n  pulse_energy_uj: 0.002\n";
// A spinning sensor from scratch (no base): its own sequence period and laser table.
std::string spinning(int period_us = 20, int first_elevation_deg = -10) {
    return "name: four\nspinning:\n  rpm: 600\n  sequence_period_us: " + std::to_string(period_us) +
           "\n  lasers:\n    - {elevation_deg: " + std::to_string(first_elevation_deg) +
           ", azimuth_offset_deg: 0, firing_offset_us: 0}\n"
           "    - {elevation_deg: -5, azimuth_offset_deg: 0, firing_offset_us: 5}\n"
           "    - {elevation_deg: -2, azimuth_offset_deg: 0, firing_offset_us: 10}\n"
           "    - {elevation_deg: 1, azimuth_offset_deg: 0, firing_offset_us: 15}\n";
}
// The airborne preset as a polygon scanner.
std::string polygon(int facets) {
    return "base: als-mirror\nairborne: {pattern: polygon, facets: " + std::to_string(facets) +
           "}\n";
}
const std::string kAir = "--trajectory static:0,0,300 --duration 0.02";
// The linear-mode waveform detector with its defaults, and with one setting changed.
const std::string kLinear = kVlp16 + "detector: {type: linear}\n";
std::string linear(const std::string& setting) {
    return kVlp16 + "detector: {type: linear, " + setting + "}\n";
}

// The Geiger-mode detector with its defaults, with settings, and a 2 × 2 flash array.
const std::string kGeiger = kVlp16 + "detector: {type: geiger}\n";
std::string geiger(const std::string& settings) {
    return kVlp16 + "detector: {type: geiger, " + settings + "}\n";
}
const std::string kMany = "max_events: 3, dark_count_rate_khz: 20000";  // several events a gate
const std::string kArray = kVlp16 + "array: {columns: 2, rows: 2}\n";
std::string array(const std::string& settings) {
    return kVlp16 + "array: {columns: 2, rows: 2, " + settings + "}\n";
}
const std::string kArrayRun = "--trajectory static:0,0,1.5 --duration 0.01";
// The ALIRT-like array with several noise events a gate (free-running takes a fixed pulse rate).
const std::string kGmapdMany =
    "base: gmapd-32x32\ndetector:\n  max_events: 3\n  dark_count_rate_khz: 20000\n";

std::vector<KeyCase> cases() {
    const std::string geo = "georef: {epsg: 32632, anchor: [500000, 5000000, 200]}\n";
    const std::string ramp =
        "function: {kind: ramp, height: 0, slope: [0.05, 0]}, size: [60, 60], cell_size: 2";
    const std::string day = "--sun-elevation-deg 60";
    return {
        // Scene file: the file's own keys.
        {"description", "description: a\n" + scene(kBox), "description: b\n" + scene(kBox), "", "",
         "", Expect::TextDiffers},
        {"epsg", scene(kBox, "{reflectance: 0.5}", geo),
         scene(kBox, "{reflectance: 0.5}",
               "georef: {epsg: 32633, anchor: [500000, 5000000, 200]}\n")},
        {"anchor", scene(kBox, "{reflectance: 0.5}", geo),
         scene(kBox, "{reflectance: 0.5}",
               "georef: {epsg: 32632, anchor: [500100, 5000000, 200]}\n")},
        {"lat", scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.1, lon: 11.5}\n"),
         scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.0, lon: 11.5}\n")},
        {"lon", scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.1, lon: 11.5}\n"),
         scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.1, lon: 11.6}\n")},
        {"h", scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.1, lon: 11.5, h: 0}\n"),
         scene(kBox, "{reflectance: 0.5}", "georef: {lat: 48.1, lon: 11.5, h: 500}\n")},
        // Materials.
        {"reflectance", material("reflectance: 0.5"), material("reflectance: 0.3")},
        {"specular", material("reflectance: 0.5"), material("reflectance: 0.5, specular: 0.3")},
        {"specular_exponent", material("reflectance: 0.5, specular: 0.3"),
         material("reflectance: 0.5, specular: 0.3, specular_exponent: 3")},
        {"retroreflective", material("reflectance: 0.5"),
         material("reflectance: 0.5, retroreflective: true")},
        {"retro_gain", material("reflectance: 0.5, retroreflective: true"),
         material("reflectance: 0.5, retroreflective: true, retro_gain: 1000")},
        {"classification", material("reflectance: 0.5"),
         material("reflectance: 0.5, classification: 9")},
        {"color", material("reflectance: 0.5"), material("reflectance: 0.5, color: [10, 200, 30]"),
         "", "", "--format 7"},
        {"transmission", material("reflectance: 0.5"),
         material("reflectance: 0.5, transmission: 0.3")},
        {"mirror", material("reflectance: 0.2"), material("reflectance: 0.2, mirror: 0.5")},
        {"refractive_index", glass_box("reflectance: 0"),
         glass_box("reflectance: 0, refractive_index: 1.5")},
        // Objects.
        {"type", scene(kBox),
         scene("{type: sphere, material: m, radius: 1.5, transform: {translate: [8, 0, 1.5]}}")},
        {"material", scene(kBox),
         scene("{type: box, material: m2, size: [3, 3, 3], transform: {translate: [8, 0, 1.5]}}")},
        {"name", scene(box_with("name: kiosk, transform: {translate: [8, 0, 1.5]}")),
         scene(box_with("name: shed, transform: {translate: [8, 0, 1.5]}")), "", "", "",
         Expect::TextDiffers},
        {"size", scene(kBox),
         scene("{type: box, material: m, size: [3, 5, 3], transform: {translate: [8, 0, 1.5]}}")},
        {"translate", scene(kBox), scene(box_with("transform: {translate: [9, 0, 1.5]}"))},
        {"rotate_deg", scene(kBox), scene(box_at("rotate_deg: [0, 0, 30]"))},
        {"quaternion", scene(kBox), scene(box_at("quaternion: [0.9659, 0, 0, 0.2588]"))},
        {"scale", scene(kBox), scene(box_at("scale: [1, 2, 1]"))},
        {"instances", scene(box_with("instances: [{translate: [8, 0, 1.5]}]")),
         scene(box_with("instances: [{translate: [8, 0, 1.5]}, {translate: [-8, 0, 1.5]}]"))},
        {"file", scene("{type: mesh, material: m, file: a.obj}"),
         scene("{type: mesh, material: m, file: b.ply}")},
        {"radius",
         scene("{type: sphere, material: m, radius: 1.5, transform: {translate: [8, 0, 1.5]}}"),
         scene("{type: sphere, material: m, radius: 2, transform: {translate: [8, 0, 1.5]}}")},
        {"subdivisions",
         scene("{type: sphere, material: m, radius: 2, subdivisions: 1, transform: {translate: [8, "
               "0, 1.5]}}"),
         scene("{type: sphere, material: m, radius: 2, subdivisions: 3, transform: {translate: [8, "
               "0, 1.5]}}")},
        {"raster", scene(ground("raster: a.pgm, cell_size: 4")),
         scene(ground("raster: b.pgm, cell_size: 4"))},
        {"cell_size", scene(ground("raster: a.pgm, cell_size: 4")),
         scene(ground("raster: a.pgm, cell_size: 5"))},
        {"z_scale", scene(ground("raster: a.pgm, cell_size: 4, z_scale: 0.01")),
         scene(ground("raster: a.pgm, cell_size: 4, z_scale: 0.02"))},
        {"z_offset", scene(ground("raster: a.pgm, cell_size: 4")),
         scene(ground("raster: a.pgm, cell_size: 4, z_offset: 0.3"))},
        {"function",
         scene(ground("function: {kind: flat, height: 0.2}, size: [60, 60], cell_size: 2")),
         scene(ground(ramp))},
        {"kind", scene(ground(ramp)),
         scene(ground("function: {kind: sine_hills, height: 0, amplitude: 0.5, wavelength: 20}, "
                      "size: [60, 60], cell_size: 2"))},
        {"height",
         scene(ground("function: {kind: flat, height: 0.2}, size: [60, 60], cell_size: 2")),
         scene(ground("function: {kind: flat, height: 0.4}, size: [60, 60], cell_size: 2"))},
        {"slope", scene(ground(ramp)),
         scene(ground("function: {kind: ramp, height: 0, slope: [0.02, 0.03]}, size: [60, 60], "
                      "cell_size: 2"))},
        {"amplitude",
         scene(ground("function: {kind: sine_hills, height: 0, amplitude: 0.5, wavelength: 20}, "
                      "size: [60, 60], cell_size: 2")),
         scene(ground("function: {kind: sine_hills, height: 0, amplitude: 0.8, wavelength: 20}, "
                      "size: [60, 60], cell_size: 2"))},
        {"wavelength",
         scene(ground("function: {kind: sine_hills, height: 0, amplitude: 0.5, wavelength: 20}, "
                      "size: [60, 60], cell_size: 2")),
         scene(ground("function: {kind: sine_hills, height: 0, amplitude: 0.5, wavelength: 30}, "
                      "size: [60, 60], cell_size: 2"))},

        // Sensor file.
        {"base", "", "", "base: vlp16\n", "base: vlp16-hires\n"},
        {"name", "", "", kVlp16 + "name: front\n", kVlp16 + "name: rear\n", "",
         Expect::TextDiffers},
        {"point_source_id", "", "", kVlp16, kVlp16 + "point_source_id: 7\n"},
        {"beam.wavelength_nm", "", "", kVlp16, kVlp16 + "beam: {wavelength_nm: 1550}\n"},
        {"beam.laser_bandwidth_nm", "", "", kVlp16, kVlp16 + "beam: {laser_bandwidth_nm: 60}\n"},
        {"beam.pulse_energy_uj", "", "", kVlp16, kVlp16 + "beam: {pulse_energy_uj: 0.2}\n"},
        {"beam.pulse_width_ns", "", "", kWeak, kWeak + "  pulse_width_ns: 20\n", day},
        {"beam.divergence_mrad", "", "", kVlp16 + "beam: {sub_rays: 7}\n",
         kVlp16 + "beam: {sub_rays: 7, divergence_mrad: 6}\n"},
        {"beam.profile", "", "", kVlp16 + "beam: {sub_rays: 7}\n",
         kVlp16 + "beam: {sub_rays: 7, profile: tophat}\n"},
        {"beam.sub_rays", "", "", kVlp16, kVlp16 + "beam: {sub_rays: 7}\n"},
        {"beam.pulse_shape", "", "", kLinear, kLinear + "beam: {pulse_shape: pulse.txt}\n"},
        {"beam.energy_sigma", "", "", kVlp16, kVlp16 + "beam: {energy_sigma: 0.2}\n"},
        {"beam.footprint_radius", "", "", kVlp16 + "beam: {sub_rays: 7}\n",
         kVlp16 + "beam: {sub_rays: 7, footprint_radius: 2}\n"},
        {"beam.footprint", "", "", kVlp16 + "beam: {sub_rays: 19}\n",
         kVlp16 + "beam: {sub_rays: 19, footprint: adaptive}\n"},
        {"detector.type", "", "", kVlp16, kLinear},
        {"detector.sample_rate_gsps", "", "", kLinear, linear("sample_rate_gsps: 2")},
        {"detector.bits", "", "", kLinear, linear("bits: 8")},
        {"detector.offset_counts", "", "", kLinear, linear("offset_counts: 4000")},
        {"detector.gain_counts_per_pe", "", "", kLinear, linear("gain_counts_per_pe: 1")},
        {"detector.apd_gain", "", "", kLinear, linear("apd_gain: 200")},
        {"detector.apd_k", "", "", kLinear, linear("apd_k: 0.5")},
        {"detector.thermal_noise_pe", "", "", kLinear, linear("thermal_noise_pe: 20")},
        {"detector.dark_current_na", "", "", kLinear, linear("dark_current_na: 100")},
        {"detector.threshold_counts", "", "", kLinear, linear("threshold_counts: 500")},
        {"detector.timing", "", "", kLinear, linear("timing: constant_fraction")},
        {"detector.cfd_fraction", "", "", linear("timing: constant_fraction"),
         linear("timing: constant_fraction, cfd_fraction: 0.2")},
        {"detector.pde", "", "", kGeiger, geiger("pde: 0.05")},
        {"detector.bin_ns", "", "", kGeiger, geiger("bin_ns: 2")},
        {"detector.dark_count_rate_khz", "", "", kGeiger, geiger("dark_count_rate_khz: 20000")},
        {"detector.dead_time_ns", "", "", geiger(kMany), geiger(kMany + ", dead_time_ns: 5")},
        {"detector.paralyzable", "", "", geiger(kMany), geiger(kMany + ", paralyzable: true")},
        {"detector.jitter_ns", "", "", kGeiger, geiger("jitter_ns: 1")},
        {"detector.afterpulse_probability", "", "", geiger(kMany),
         geiger(kMany + ", afterpulse_probability: 0.5")},
        {"detector.afterpulse_delay_ns", "", "", geiger(kMany + ", afterpulse_probability: 0.5"),
         geiger(kMany + ", afterpulse_probability: 0.5, afterpulse_delay_ns: 10")},
        {"detector.max_events", "", "", geiger("dark_count_rate_khz: 20000"), geiger(kMany)},
        {"detector.crosstalk_probability", "", "", geiger(kMany) + "array: {columns: 2, rows: 2}\n",
         geiger(kMany + ", crosstalk_probability: 0.5") + "array: {columns: 2, rows: 2}\n",
         kArrayRun},
        {"detector.free_running", "", "", kGmapdMany, kGmapdMany + "  free_running: true\n",
         "--trajectory static:0,0,1200 --duration 0.002"},
        {"array.columns", "", "", kArray, kVlp16 + "array: {columns: 3, rows: 2}\n", kArrayRun},
        {"array.rows", "", "", kArray, kVlp16 + "array: {columns: 2, rows: 3}\n", kArrayRun},
        {"array.pitch_um", "", "", kArray, array("pitch_um: 200"), kArrayRun},
        {"array.focal_length_mm", "", "", kArray, array("focal_length_mm: 100"), kArrayRun},
        {"array.fill_factor", "", "", kArray, array("fill_factor: 0.5"), kArrayRun},
        {"array.illumination", "", "", kArray, array("illumination: beamlets"), kArrayRun},
        {"receiver.aperture_mm", "", "", kVlp16, kVlp16 + "receiver: {aperture_mm: 30}\n"},
        {"receiver.f_number", "", "", kVlp16, kVlp16 + "receiver: {f_number: 2}\n", day},
        {"receiver.detector_area_mm2", "", "", kVlp16,
         kVlp16 + "receiver: {detector_area_mm2: 0.001}\n"},
        {"receiver.eta_transmitter", "", "", kVlp16, kVlp16 + "receiver: {eta_transmitter: 0.5}\n"},
        {"receiver.eta_receiver", "", "", kVlp16, kVlp16 + "receiver: {eta_receiver: 0.5}\n"},
        {"receiver.quantum_efficiency", "", "", kVlp16,
         kVlp16 + "receiver: {quantum_efficiency: 0.5}\n"},
        {"receiver.detector_bandwidth_nm", "", "", kWeak,
         kWeak + "receiver: {detector_bandwidth_nm: 200}\n", day},
        {"receiver.integration_time_ns", "", "", kVlp16,
         kVlp16 + "receiver: {integration_time_ns: 5000}\n", day},
        {"receiver.noise_irradiance_sigma", "", "", kVlp16,
         kVlp16 + "receiver: {noise_irradiance_sigma: 40}\n"},
        {"receiver.threshold_gamma", "", "", kVlp16, kVlp16 + "receiver: {threshold_gamma: 30}\n"},
        {"receiver.min_range_m", "", "", kVlp16, kVlp16 + "receiver: {min_range_m: 7}\n"},
        {"receiver.max_range_m", "", "", kVlp16, kVlp16 + "receiver: {max_range_m: 20}\n"},
        {"receiver.range_resolution_m", "", "", kVlp16,
         kVlp16 + "receiver: {range_resolution_m: 0.1}\n"},
        {"receiver.max_returns", "", "", kVlp16 + "beam: {sub_rays: 19, divergence_mrad: 30}\n",
         kVlp16 + "beam: {sub_rays: 19, divergence_mrad: 30}\nreceiver: {max_returns: 3}\n"},
        {"receiver.diffuse_bounces", "", "", kVlp16 + "receiver: {detector_area_mm2: 50}\n",
         kVlp16 + "receiver: {detector_area_mm2: 50, diffuse_bounces: 1}\n"},
        {"receiver.max_path_depth", material("reflectance: 0.5, transmission: 0.3"),
         material("reflectance: 0.5, transmission: 0.3"), kVlp16,
         kVlp16 + "receiver: {max_path_depth: 1}\n"},
        {"receiver.path_energy_threshold", material("reflectance: 0.5, transmission: 0.3"),
         material("reflectance: 0.5, transmission: 0.3"), kVlp16,
         kVlp16 + "receiver: {path_energy_threshold: 0.5}\n"},
        {"receiver.speckle_cells", "", "", kVlp16, kVlp16 + "receiver: {speckle_cells: 2}\n"},
        {"receiver.overlap_range_m", "", "", kLinear, kLinear + "receiver: {overlap_range_m: 20}\n",
         "--lidar-ratio 20 --visibility-km 0.3"},
        {"noise.range_sigma_m", "", "", kVlp16, kVlp16 + "noise: {range_sigma_m: 0.1}\n"},
        {"noise.jitter_sigma_mrad", "", "", kVlp16, kVlp16 + "noise: {jitter_sigma_mrad: 1}\n"},
        {"spinning.rpm", "", "", kVlp16, kVlp16 + "spinning: {rpm: 900}\n"},
        {"spinning.sequence_period_us", "", "", spinning(), spinning(30)},
        {"spinning.lasers", "", "", spinning(), spinning(20, -12)},
        {"airborne.pattern", "", "", kAls, kAls + "airborne: {pattern: sine}\n", kAir},
        {"airborne.prf_khz", "", "", kAls, kAls + "airborne: {prf_khz: 300}\n", kAir},
        {"airborne.scan_rate_hz", "", "", kAls, kAls + "airborne: {scan_rate_hz: 70}\n", kAir},
        {"airborne.fov_deg", "", "", kAls, kAls + "airborne: {fov_deg: 30}\n", kAir},
        {"airborne.facets", "", "", polygon(4), polygon(6), kAir},
        {"airborne.tilt_deg", "", "", kAls, kAls + "airborne: {tilt_deg: 10}\n", kAir},
    };
}

std::string read_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void write_file(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// The mesh, raster and pulse inputs the cases name: two different OBJ/PLY meshes, PGM rasters
// and a measured pulse shape.
void write_inputs(const std::filesystem::path& dir) {
    write_file(dir / "pulse.txt", "0 0\n1 1\n6 0\n");
    write_file(dir / "a.obj", "v 6 -2 0\nv 10 -2 0\nv 8 2 3\nf 1 2 3\n");
    write_file(dir / "b.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n6 -2 0\n10 -2 0\n8 3 4\n3 0 1 2\n");
    for (const char* name : {"a.pgm", "b.pgm"}) {
        std::string pgm = "P5\n8 8\n255\n";
        for (int i = 0; i < 64; ++i)
            pgm.push_back(static_cast<char>(name[0] == 'a' ? (i * 7) % 50 : (i * 11) % 80));
        write_file(dir / name, pgm);
    }
}

struct Render {
    RunResult run;
    std::string las;
    std::string labels;  // the start-up lines naming the scene and the sensor, paths removed
};

// Keeps the lines that describe the scene and the sensor, without the run's folder.
std::string labels_of(const std::string& output, const std::string& folder) {
    std::string out;
    std::size_t pos = 0;
    while (pos < output.size()) {
        const std::size_t end = std::min(output.find('\n', pos), output.size());
        std::string line = output.substr(pos, end - pos);
        pos = end + 1;
        if (line.rfind("scene '", 0) != 0 && line.rfind("sensor '", 0) != 0) continue;
        for (std::size_t at = line.find(folder); at != std::string::npos; at = line.find(folder))
            line.erase(at, folder.size());
        out += line + "\n";
    }
    return out;
}

// One run in its own folder, with the same file names as the other run of its case.
Render render(const TempDir& dir, const std::string& tag, const std::string& scene_yaml,
              const std::string& sensor_yaml, const std::string& args) {
    const std::filesystem::path folder = dir.path() / tag;
    std::filesystem::create_directories(folder);
    write_inputs(folder);
    write_file(folder / "scene.yaml", scene_yaml.empty() ? scene(kBox) : scene_yaml);
    write_file(folder / "sensor.yaml", sensor_yaml.empty() ? kVlp16 : sensor_yaml);
    const std::string a = args.find("--trajectory") == std::string::npos
                              ? "--trajectory static:0,0,1.5 --duration 0.1 " + args
                              : args;
    Render r;
    r.run = run_mirage("render --scene " + (folder / "scene.yaml").string() + " --sensor " +
                       (folder / "sensor.yaml").string() + " --seed 3 --threads 1 " + a +
                       " --out " + (folder / "out.las").string());
    r.las = read_file((folder / "out.las").string());
    r.labels = labels_of(r.run.output, folder.string() + "/");
    return r;
}

TEST(DocumentedKeys, changing_each_key_changes_the_output_or_is_refused) {
    TempDir dir;
    for (const KeyCase& c : cases()) {
        SCOPED_TRACE("key " + c.key);
        const Render a = render(dir, "a", c.scene_a, c.sensor_a, c.args);
        const Render b = render(dir, "b", c.scene_b, c.sensor_b, c.args);
        ASSERT_EQ(a.run.exit_code, 0) << a.run.output;
        if (c.expect == Expect::Refused) {
            EXPECT_EQ(b.run.exit_code, 2) << b.run.output;
            EXPECT_NE(b.run.output.find(c.key), std::string::npos) << b.run.output;
            continue;
        }
        ASSERT_EQ(b.run.exit_code, 0) << b.run.output;
        ASSERT_GT(a.las.size(), 400u);
        if (c.expect == Expect::TextDiffers)
            EXPECT_NE(a.labels, b.labels) << a.labels;
        else
            EXPECT_NE(a.las, b.las) << "changing " << c.key << " left the LAS file unchanged";
    }
}

// A key the docs describe must be one of the cases above (and a case must name a documented key).
TEST(DocumentedKeys, every_key_in_the_docs_has_a_case) {
    const std::string formats = read_file((source_dir() / "docs/file-formats.md").string());
    const std::string sensors = read_file((source_dir() / "docs/sensors.md").string());
    ASSERT_FALSE(formats.empty());
    ASSERT_FALSE(sensors.empty());
    std::vector<std::string> keys;
    for (const KeyCase& c : cases()) keys.push_back(c.key);
    for (const std::string& k : keys) {
        const bool sensor_key =
            k.find('.') != std::string::npos || k == "base" || k == "point_source_id";
        const std::string& doc = sensor_key ? sensors : formats;
        EXPECT_NE(doc.find(k), std::string::npos) << "case '" << k << "' is not in the docs";
    }
    // The sensor-file table: every `key` in its first column has a case.
    std::size_t pos = sensors.find("| key | meaning |");
    ASSERT_NE(pos, std::string::npos);
    for (pos = sensors.find("\n| `", pos); pos != std::string::npos;
         pos = sensors.find("\n| `", pos + 1)) {
        const std::size_t cell_end = sensors.find(" |", pos + 3);
        const std::string cell = sensors.substr(pos + 3, cell_end - pos - 3);
        for (std::size_t q = cell.find('`'); q != std::string::npos; q = cell.find('`', q + 1)) {
            const std::size_t e = cell.find('`', q + 1);
            const std::string key = cell.substr(q + 1, e - q - 1);
            q = e;
            EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end())
                << "docs/sensors.md documents '" << key << "' but no case changes it";
        }
    }
}

}  // namespace
}  // namespace mirage::test
