// SPDX-License-Identifier: Apache-2.0
// Sensor YAML: `base: <preset>` (optional), then overrides (see recordings/sensors/*.yaml).
// Every key is checked against a fixed list and every value against a range; errors name the
// key path, e.g. "sensor 'x.yaml': beam.sub_rays: 5 is not a hexagonal count (1, 7, 19, 37, …)".
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/airborne.hpp"
#include "mirage/sensor/array.hpp"
#include "mirage/sensor/pulse_table.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/sensor/spinning.hpp"

namespace mirage::sensor {
namespace {

constexpr int kMaxSubRays = 331;  // 10 rings

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::string join_path(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

// Reads one file, remembering its label for error messages.
class Reader {
  public:
    explicit Reader(std::string path) : path_(std::move(path)) {}

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw ConfigError("sensor '" + path_ + "': " + (key.empty() ? "" : key + ": ") + what);
    }

    // `text`: the YAML itself, or nullptr to read the file.
    YAML::Node load(const std::string* text) const {
        if (!text && !std::filesystem::is_regular_file(path_))
            throw IoError("sensor '" + path_ + "': cannot open file");
        try {
            return text ? YAML::Load(*text) : YAML::LoadFile(path_);
        } catch (const YAML::BadFile&) {
            throw IoError("sensor '" + path_ + "': cannot open file");
        } catch (const YAML::ParserException& e) {
            fail("", "line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
        }
    }

    void map(const YAML::Node& n, const std::string& key) const {
        if (!n.IsMap()) fail(key, "expected a mapping of keys");
    }

    void only_keys(const YAML::Node& n, const std::string& parent,
                   std::initializer_list<const char*> allowed) const {
        map(n, parent);
        for (const auto& kv : n) {
            if (!kv.first.IsScalar()) fail(parent, "keys must be plain names");
            const std::string k = kv.first.Scalar();
            if (std::none_of(allowed.begin(), allowed.end(),
                             [&](const char* a) { return k == a; })) {
                std::string list;
                for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                fail(join_path(parent, k), "unknown key (expected one of " + list + ")");
            }
        }
    }

    double number(const YAML::Node& n, const std::string& key) const {
        if (!n.IsScalar()) fail(key, "expected a number");
        double v = 0;
        try {
            v = n.as<double>();
        } catch (const YAML::Exception&) {
            fail(key, "expected a number, got '" + n.Scalar() + "'");
        }
        if (!std::isfinite(v)) fail(key, "expected a finite number, got '" + n.Scalar() + "'");
        return v;
    }

    // lo ≤ v ≤ hi, with open ends where asked.
    double number(const YAML::Node& n, const std::string& key, double lo, double hi,
                  bool lo_open = false, bool hi_open = false) const {
        const double v = number(n, key);
        const bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
        if (!ok)
            fail(key, num(v) + " is outside " + (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) +
                          (hi_open ? ")" : "]"));
        return v;
    }

    long long integer(const YAML::Node& n, const std::string& key, long long lo,
                      long long hi) const {
        if (!n.IsScalar()) fail(key, "expected an integer");
        long long v = 0;
        try {
            v = n.as<long long>();
        } catch (const YAML::Exception&) {
            fail(key, "expected an integer, got '" + n.Scalar() + "'");
        }
        if (v < lo || v > hi)
            fail(key, std::to_string(v) + " is outside [" + std::to_string(lo) + ", " +
                          std::to_string(hi) + "]");
        return v;
    }

    // n[key] into `out` when it is there, checked as number() does.
    void maybe(const YAML::Node& n, const std::string& parent, const char* key, double lo,
               double hi, bool lo_open, double& out) const {
        if (n[key]) out = number(n[key], join_path(parent, key), lo, hi, lo_open);
    }

    std::string text(const YAML::Node& n, const std::string& key) const {
        if (!n.IsScalar()) fail(key, "expected a string");
        return n.Scalar();
    }

    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

// `beam.pulse_shape`: `gaussian` (of pulse_width_ns) or a file of the measured shape, relative
// to the sensor file; its FWHM becomes the pulse width, so pulse_width_ns may not be given too.
void read_pulse_shape(const Reader& r, const YAML::Node& n, BeamParams& b) {
    const std::string v = r.text(n["pulse_shape"], "beam.pulse_shape");
    b.pulse_t_ns.clear();
    b.pulse_power.clear();
    b.pulse_shape_file.clear();
    if (v == "gaussian") return;
    if (n["pulse_width_ns"])
        r.fail("beam.pulse_width_ns", "comes from the FWHM of beam.pulse_shape '" + v + "'");
    const std::filesystem::path file = std::filesystem::path(v).is_absolute()
                                           ? std::filesystem::path(v)
                                           : std::filesystem::path(r.path()).parent_path() / v;
    PulseTable t;
    try {
        t = load_pulse_table(file.string());
    } catch (const IoError& e) {
        r.fail("beam.pulse_shape", e.what());
    } catch (const ConfigError& e) {
        r.fail("beam.pulse_shape", e.what());
    }
    b.pulse_width_s = 1e-9 * t.fwhm_ns;
    b.pulse_t_ns = std::move(t.t_ns);
    b.pulse_power = std::move(t.power);
    b.pulse_shape_file = file.string();
}

void read_beam(const Reader& r, const YAML::Node& n, BeamParams& b) {
    r.only_keys(n, "beam",
                {"wavelength_nm", "pulse_energy_uj", "pulse_width_ns", "divergence_mrad", "profile",
                 "sub_rays", "laser_bandwidth_nm", "footprint_radius", "pulse_shape",
                 "energy_sigma", "footprint"});
    if (n["wavelength_nm"])
        b.wavelength_m = 1e-9 * r.number(n["wavelength_nm"], "beam.wavelength_nm", 200, 12000);
    if (n["pulse_energy_uj"])
        b.pulse_energy_j =
            1e-6 * r.number(n["pulse_energy_uj"], "beam.pulse_energy_uj", 0, 1e5, true);
    if (n["pulse_width_ns"])
        b.pulse_width_s = 1e-9 * r.number(n["pulse_width_ns"], "beam.pulse_width_ns", 0, 1e4, true);
    if (n["divergence_mrad"])
        b.divergence_rad = 1e-3 * r.number(n["divergence_mrad"], "beam.divergence_mrad", 0, 100);
    if (n["laser_bandwidth_nm"])
        b.laser_bandwidth_m =
            1e-9 * r.number(n["laser_bandwidth_nm"], "beam.laser_bandwidth_nm", 0, 1000, true);
    if (n["profile"]) {
        const std::string p = r.text(n["profile"], "beam.profile");
        if (p == "gaussian") {
            b.profile = BeamProfile::Gaussian;
        } else if (p == "tophat") {
            b.profile = BeamProfile::TopHat;
        } else {
            r.fail("beam.profile", "'" + p + "' is not gaussian or tophat");
        }
    }
    if (n["pulse_shape"]) read_pulse_shape(r, n, b);
    if (n["energy_sigma"])
        b.energy_sigma = r.number(n["energy_sigma"], "beam.energy_sigma", 0, 1, false);
    if (n["footprint_radius"]) {
        b.footprint_radius = r.number(n["footprint_radius"], "beam.footprint_radius", 0, 3, true);
        if (b.profile == BeamProfile::TopHat && b.footprint_radius != 1.0)
            r.fail("beam.footprint_radius",
                   "a top-hat beam has no light beyond its radius (use 1)");
    }
    if (n["footprint"]) {
        const std::string f = r.text(n["footprint"], "beam.footprint");
        if (f != "sampled" && f != "adaptive")
            r.fail("beam.footprint", "'" + f + "' is not sampled or adaptive");
        b.adaptive_footprint = f == "adaptive";
    }
    if (n["sub_rays"]) {
        const auto v = r.integer(n["sub_rays"], "beam.sub_rays", -1'000'000, 1'000'000);
        if (!is_hex_count(static_cast<int>(v)))
            r.fail("beam.sub_rays",
                   std::to_string(v) + " is not a hexagonal count (1, 7, 19, 37, …)");
        if (v > kMaxSubRays)
            r.fail("beam.sub_rays",
                   std::to_string(v) + " exceeds " + std::to_string(kMaxSubRays) + " (10 rings)");
        b.sub_rays = static_cast<int>(v);
    }
}

void read_receiver(const Reader& r, const YAML::Node& n, ReceiverParams& x) {
    r.only_keys(n, "receiver",
                {"aperture_mm", "f_number", "detector_area_mm2", "eta_transmitter", "eta_receiver",
                 "quantum_efficiency", "detector_bandwidth_nm", "integration_time_ns",
                 "noise_irradiance_sigma", "threshold_gamma", "min_range_m", "max_range_m",
                 "range_resolution_m", "max_returns", "max_path_depth", "path_energy_threshold",
                 "diffuse_bounces", "overlap_range_m", "speckle_cells"});
    const auto get = [&](const char* key, double lo, double hi, bool lo_open, double scale,
                         double& out) {
        if (n[key]) out = scale * r.number(n[key], join_path("receiver", key), lo, hi, lo_open);
    };
    get("aperture_mm", 0, 2000, true, 1e-3, x.aperture_diameter_m);
    get("f_number", 0, 100, true, 1.0, x.f_number);
    get("detector_area_mm2", 0, 1e4, true, 1e-6, x.detector_area_m2);
    get("eta_transmitter", 0, 1, true, 1.0, x.eta_transmitter);
    get("eta_receiver", 0, 1, true, 1.0, x.eta_receiver);
    get("quantum_efficiency", 0, 1, true, 1.0, x.quantum_efficiency);
    get("detector_bandwidth_nm", 0, 1000, true, 1e-9, x.detector_bandwidth_m);
    get("integration_time_ns", 0, 1e9, false, 1e-9, x.integration_time_s);
    get("noise_irradiance_sigma", 0, 1e12, false, 1.0, x.noise_irradiance_sigma);
    get("threshold_gamma", 0, 1e6, false, 1.0, x.threshold_gamma);
    get("min_range_m", 0, 1e6, false, 1.0, x.min_range_m);
    get("max_range_m", 0, 1e6, true, 1.0, x.max_range_m);
    get("range_resolution_m", 0, 10, false, 1.0, x.range_resolution_m);
    if (n["max_returns"])
        x.max_returns =
            static_cast<int>(r.integer(n["max_returns"], "receiver.max_returns", 1, kMaxReturns));
    if (n["max_path_depth"])
        x.max_path_depth = static_cast<int>(
            r.integer(n["max_path_depth"], "receiver.max_path_depth", 1, kMaxPathDepth));
    get("path_energy_threshold", 0, 1, false, 1.0, x.path_energy_threshold);
    if (n["diffuse_bounces"])
        x.diffuse_bounces = static_cast<int>(
            r.integer(n["diffuse_bounces"], "receiver.diffuse_bounces", 0, kMaxPathDepth - 1));
    get("overlap_range_m", 0, 1e4, false, 1.0, x.overlap_range_m);
    if (const YAML::Node m = n["speckle_cells"]) {  // auto, 0 (off) or M ≥ 1
        const char* key = "receiver.speckle_cells";
        if (m.IsScalar() && m.Scalar() == "auto")
            x.speckle_cells = kSpeckleAuto;
        else
            x.speckle_cells = r.number(m, key) == 0 ? 0.0 : r.number(m, key, 1, 1e9);
    }
    if (x.min_range_m >= x.max_range_m)
        r.fail(n["max_range_m"] ? "receiver.max_range_m" : "receiver.min_range_m",
               "min_range_m " + num(x.min_range_m) + " must be below max_range_m " +
                   num(x.max_range_m));
}

void read_noise(const Reader& r, const YAML::Node& n, NoiseParams& x) {
    r.only_keys(n, "noise", {"range_sigma_m", "jitter_sigma_mrad"});
    if (n["range_sigma_m"])
        x.range_sigma_m = r.number(n["range_sigma_m"], "noise.range_sigma_m", 0, 100);
    if (n["jitter_sigma_mrad"])
        x.jitter_sigma_rad =
            1e-3 * r.number(n["jitter_sigma_mrad"], "noise.jitter_sigma_mrad", 0, 100);
}

// `detector.timing` (peak, constant_fraction, decomposition) and `detector.cfd_fraction`, which
// only the constant-fraction timing reads.
void read_echo_timing(const Reader& r, const YAML::Node& n, SensorModel& m) {
    LinearDetectorParams& p = m.linear;
    if (n["timing"]) {
        const std::string t = r.text(n["timing"], "detector.timing");
        if (t == "peak")
            p.timing = EchoTiming::Peak;
        else if (t == "constant_fraction")
            p.timing = EchoTiming::ConstantFraction;
        else if (t == "decomposition")
            p.timing = EchoTiming::Decomposition;
        else
            r.fail("detector.timing",
                   "'" + t + "' is not peak, constant_fraction or decomposition");
    }
    if (n["cfd_fraction"]) {
        if (p.timing != EchoTiming::ConstantFraction)
            r.fail("detector.cfd_fraction", "only with detector.timing: constant_fraction");
        p.cfd_fraction = r.number(n["cfd_fraction"], "detector.cfd_fraction", 0.01, 0.99);
    }
}

// `detector:` with type geiger (docs/photon-counting.md §2): timing, dark counts, dead time,
// jitter, afterpulses; `pde` sets the receiver's quantum efficiency (it is the same number).
void read_geiger(const Reader& r, const YAML::Node& n, SensorModel& m) {
    GeigerDetectorParams& p = m.geiger;
    r.maybe(n, "detector", "bin_ns", 0, 1e3, true, p.bin_ns);
    r.maybe(n, "detector", "dead_time_ns", 0, 1e9, false, p.dead_time_ns);
    r.maybe(n, "detector", "jitter_ns", 0, 1e3, false, p.jitter_ns);
    r.maybe(n, "detector", "afterpulse_probability", 0, 1, false, p.afterpulse_probability);
    r.maybe(n, "detector", "afterpulse_delay_ns", 0, 1e9, true, p.afterpulse_delay_ns);
    r.maybe(n, "detector", "crosstalk_probability", 0, 1, false, p.crosstalk_probability);
    r.maybe(n, "detector", "pde", 0, 1, true, m.receiver.quantum_efficiency);
    if (n["dark_count_rate_khz"])
        p.dark_count_rate_hz =
            1e3 * r.number(n["dark_count_rate_khz"], "detector.dark_count_rate_khz", 0, 1e6);
    for (const auto& [key, flag] :
         {std::pair{"paralyzable", &p.paralyzable}, std::pair{"free_running", &p.free_running}}) {
        if (!n[key]) continue;
        const std::string path = join_path("detector", key);
        const std::string v = r.text(n[key], path);
        if (v != "true" && v != "false") r.fail(path, "'" + v + "' is not true or false");
        *flag = v == "true";
    }
    if (n["max_events"])
        p.max_events = static_cast<int>(r.integer(n["max_events"], "detector.max_events", 1, 15));
}

// The settings only one detector type reads are refused with another, where they would do nothing.
void check_detector_keys(const Reader& r, const YAML::Node& n, DetectorKind kind) {
    static const char* const linear[] = {
        "sample_rate_gsps", "bits",   "offset_counts",    "gain_counts_per_pe",
        "apd_gain",         "apd_k",  "thermal_noise_pe", "dark_current_na",
        "threshold_counts", "timing", "cfd_fraction"};
    static const char* const geiger[] = {
        "bin_ns",    "dark_count_rate_khz",    "dead_time_ns",        "paralyzable",
        "jitter_ns", "afterpulse_probability", "afterpulse_delay_ns", "max_events",
        "pde",       "crosstalk_probability",  "free_running"};
    for (const char* key : linear)
        if (n[key] && kind != DetectorKind::Linear)
            r.fail(join_path("detector", key), "only with detector.type: linear");
    for (const char* key : geiger)
        if (n[key] && kind != DetectorKind::Geiger)
            r.fail(join_path("detector", key), "only with detector.type: geiger");
}

// What a base sensor's scan is, for errors about keys that would replace it.
std::string what_scan(const ScanPattern& scan) {
    if (dynamic_cast<const SpinningPattern*>(&scan)) return "a spinning sensor";
    if (dynamic_cast<const AirbornePattern*>(&scan)) return "an airborne sensor";
    return "a " + scan.kind() + " sensor";
}

// A gated Geiger-mode pixel is armed once per laser pulse (docs/photon-counting.md §2): its gate
// must close before the next pulse fires, and a pixel that fired must be armed again by the next
// gate. A free-running one (an array only) carries its dead time into the next pulse's window.
void check_geiger_timing(const Reader& r, const SensorModel& m) {
    if (m.detector != DetectorKind::Geiger || !m.scan) return;
    constexpr double kC = 299'792'458.0;
    const double period_ns = 1e9 * double(m.scan->group_size()) / m.scan->pulse_rate_hz();
    const double open_ns = 2e9 * m.receiver.min_range_m / kC;
    const double close_ns = 2e9 * m.receiver.max_range_m / kC;
    if (close_ns >= period_ns)
        r.fail("receiver.max_range_m", "the gate closes " + num(close_ns * 1e-3) +
                                           " µs after the pulse, past the next one (every " +
                                           num(period_ns * 1e-3) + " µs)");
    if (m.geiger.free_running) {
        if (!m.array.on())
            r.fail("detector.free_running", "only for an array (a sensor with `array:`)");
        // The carry takes the next window one pulse period on: a spinning head fires its lasers
        // in bursts with idle time between, not at a fixed period.
        const ScanPattern* laser = m.scan.get();
        if (const auto* a = dynamic_cast<const ArrayScan*>(laser)) laser = &a->laser();
        if (dynamic_cast<const SpinningPattern*>(laser))
            r.fail("detector.free_running",
                   "only for a laser firing at a fixed rate (not a spinning sensor)");
        return;
    }
    if (close_ns + m.geiger.dead_time_ns > period_ns + open_ns)
        r.fail("detector.dead_time_ns",
               "a pixel firing at the gate's close would still be dead when the next gate opens "
               "(" +
                   num(close_ns * 1e-3) + " + " + num(m.geiger.dead_time_ns * 1e-3) + " > " +
                   num(period_ns * 1e-3) + " + " + num(open_ns * 1e-3) +
                   " µs); a gated array re-arms every pixel at its gate (detector.free_running: "
                   "true carries the dead time over)");
}

// `detector:`: `type: discrete` (default) or `linear` with the digitiser and APD settings
// (docs/time-resolved.md §7); those settings are refused with the discrete detector, where they
// would do nothing.
void read_detector(const Reader& r, const YAML::Node& n, SensorModel& m) {
    r.only_keys(n, "detector",
                {"type",
                 "sample_rate_gsps",
                 "bits",
                 "offset_counts",
                 "gain_counts_per_pe",
                 "apd_gain",
                 "apd_k",
                 "thermal_noise_pe",
                 "dark_current_na",
                 "threshold_counts",
                 "timing",
                 "cfd_fraction",
                 "bin_ns",
                 "dark_count_rate_khz",
                 "dead_time_ns",
                 "paralyzable",
                 "jitter_ns",
                 "afterpulse_probability",
                 "afterpulse_delay_ns",
                 "max_events",
                 "pde",
                 "crosstalk_probability",
                 "free_running"});
    if (n["type"]) {
        const std::string t = r.text(n["type"], "detector.type");
        if (t == "discrete")
            m.detector = DetectorKind::Discrete;
        else if (t == "linear")
            m.detector = DetectorKind::Linear;
        else if (t == "geiger")
            m.detector = DetectorKind::Geiger;
        else
            r.fail("detector.type", "'" + t + "' is not discrete, linear or geiger");
    }
    check_detector_keys(r, n, m.detector);
    if (m.detector == DetectorKind::Geiger) read_geiger(r, n, m);
    LinearDetectorParams& p = m.linear;  // (check_detector_keys refused these otherwise)
    r.maybe(n, "detector", "sample_rate_gsps", 0, 100, true, p.sample_rate_gsps);
    r.maybe(n, "detector", "offset_counts", 0, 4e9, false, p.offset_counts);
    r.maybe(n, "detector", "gain_counts_per_pe", 0, 1e6, true, p.gain_counts_per_pe);
    r.maybe(n, "detector", "apd_gain", 1, 1e4, false, p.apd_gain);
    r.maybe(n, "detector", "apd_k", 0, 1, false, p.apd_k);
    r.maybe(n, "detector", "thermal_noise_pe", 0, 1e6, false, p.thermal_noise_pe);
    r.maybe(n, "detector", "dark_current_na", 0, 1e6, false, p.dark_current_na);
    r.maybe(n, "detector", "threshold_counts", 0, 4e9, false, p.threshold_counts);
    read_echo_timing(r, n, m);
    if (n["bits"]) {
        p.bits = static_cast<int>(r.integer(n["bits"], "detector.bits", 1, 32));
    }
    const double full = std::ldexp(1.0, p.bits) - 1.0;
    if (p.offset_counts >= full)
        r.fail("detector.offset_counts", num(p.offset_counts) + " is not below full scale " +
                                             num(full) + " of " + std::to_string(p.bits) + " bits");
    if (p.threshold_counts >= full - p.offset_counts)
        r.fail("detector.threshold_counts", "leaves no room below full scale " + num(full));
}

// `array:` (docs/photon-counting.md §3): a focal-plane array behind the laser (columns and rows
// required unless the base preset has an array).
void read_array(const Reader& r, const YAML::Node& root, SensorModel& m) {
    const YAML::Node& n = root["array"];
    r.only_keys(n, "array",
                {"columns", "rows", "pitch_um", "focal_length_mm", "fill_factor", "illumination"});
    ArrayParams& a = m.array;
    for (const char* key : {"columns", "rows"})
        if (!n[key] && !a.on()) r.fail(join_path("array", key), "required");
    if (n["columns"])
        a.columns = static_cast<std::uint32_t>(r.integer(n["columns"], "array.columns", 1, 4096));
    if (n["rows"]) a.rows = static_cast<std::uint32_t>(r.integer(n["rows"], "array.rows", 1, 4096));
    if (n["pitch_um"]) a.pitch_m = 1e-6 * r.number(n["pitch_um"], "array.pitch_um", 0, 1e4, true);
    if (n["focal_length_mm"])
        a.focal_length_m =
            1e-3 * r.number(n["focal_length_mm"], "array.focal_length_mm", 0, 1e5, true);
    if (n["fill_factor"])
        a.fill_factor = r.number(n["fill_factor"], "array.fill_factor", 0, 1, true);
    if (n["illumination"]) {
        const std::string v = r.text(n["illumination"], "array.illumination");
        if (v == "flash")
            a.illumination = Illumination::Flash;
        else if (v == "beamlets")
            a.illumination = Illumination::Beamlets;
        else
            r.fail("array.illumination", "'" + v + "' is not flash or beamlets");
    }
}

// The array (the file's or the base preset's) made last, over the beam, receiver and scan the
// file set; the receiver's focal length and pixel area follow from it, so they may not be given.
void finish_array(const Reader& r, const YAML::Node& root, SensorModel& m) {
    if (!root["array"] && !m.array.on()) return;
    for (const char* key : {"f_number", "detector_area_mm2"})
        if (root["receiver"] && root["receiver"][key])
            r.fail(join_path("receiver", key), "set by the array (pitch_um, focal_length_mm)");
    if (root["array"]) read_array(r, root, m);
    make_array(m, "sensor '" + r.path() + "'");
}

std::shared_ptr<const ScanPattern> read_spinning(const Reader& r, const YAML::Node& n,
                                                 const SpinningPattern* base,
                                                 const std::string& base_name) {
    r.only_keys(n, "spinning", {"rpm", "lasers", "sequence_period_us"});
    SpinningConfig c;
    if (base) c = base->config();
    const bool ouster = c.family == SpinningFamily::Ouster;
    if (n["rpm"]) {
        if (ouster)
            r.fail("spinning.rpm", "Ouster presets fix the rate in the name (base '" + base_name +
                                       "'; choose …x10 or …x20)");
        const double rpm = c.family == SpinningFamily::Velodyne
                               ? r.number(n["rpm"], "spinning.rpm", 300, 1200)
                               : r.number(n["rpm"], "spinning.rpm", 0, 6000, true);
        c.rotation_hz = rpm / 60.0;
    } else if (!base) {
        c.rotation_hz = 10.0;
    }
    if (n["sequence_period_us"]) {
        if (ouster)
            r.fail("spinning.sequence_period_us",
                   "Ouster presets fix the column period 1/(W·F) (base '" + base_name + "')");
        c.sequence_period_ns =
            1e3 * r.number(n["sequence_period_us"], "spinning.sequence_period_us", 0.001, 1e6);
        c.sequence_period_ns = std::round(c.sequence_period_ns * 1e6) / 1e6;
    } else if (!base) {
        r.fail("spinning.sequence_period_us", "required when there is no base preset");
    }
    if (n["lasers"]) {
        const YAML::Node& list = n["lasers"];
        if (!list.IsSequence() || list.size() == 0)
            r.fail("spinning.lasers", "expected a non-empty list of lasers");
        if (list.size() > 65535) r.fail("spinning.lasers", "more than 65535 lasers");
        c.lasers.clear();
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string key = "spinning.lasers[" + std::to_string(i) + "]";
            const YAML::Node& l = list[i];
            r.only_keys(l, key, {"elevation_deg", "azimuth_offset_deg", "firing_offset_us"});
            LaserSpec s;
            if (!l["elevation_deg"]) r.fail(key + ".elevation_deg", "required");
            s.elevation_deg = r.number(l["elevation_deg"], key + ".elevation_deg", -90, 90);
            if (l["azimuth_offset_deg"])
                s.azimuth_offset_deg =
                    r.number(l["azimuth_offset_deg"], key + ".azimuth_offset_deg", -180, 180);
            if (l["firing_offset_us"])
                s.firing_offset_ns =
                    1e3 * r.number(l["firing_offset_us"], key + ".firing_offset_us", 0, 1e6);
            c.lasers.push_back(s);
        }
    } else if (!base) {
        r.fail("spinning.lasers", "required when there is no base preset");
    }
    for (std::size_t i = 0; i < c.lasers.size(); ++i) {
        if (std::round(c.lasers[i].firing_offset_ns) >= std::floor(c.sequence_period_ns))
            r.fail("spinning.lasers[" + std::to_string(i) + "].firing_offset_us",
                   num(c.lasers[i].firing_offset_ns * 1e-3) + " is not below the sequence period " +
                       num(c.sequence_period_ns * 1e-3) + " µs");
    }
    return std::make_shared<SpinningPattern>(std::move(c));
}

std::shared_ptr<const ScanPattern> read_airborne(const Reader& r, const YAML::Node& n,
                                                 const AirbornePattern* base) {
    r.only_keys(n, "airborne",
                {"pattern", "prf_khz", "scan_rate_hz", "fov_deg", "facets", "tilt_deg"});
    AirborneConfig c;
    if (base) c = base->config();
    const auto need = [&](const char* key) {
        if (!base && !n[key])
            r.fail(join_path("airborne", key), "required when there is no base preset");
    };
    need("pattern");
    need("prf_khz");
    need("scan_rate_hz");
    need("fov_deg");
    if (n["pattern"]) {
        const std::string p = r.text(n["pattern"], "airborne.pattern");
        if (p == "sawtooth") {
            c.kind = AirborneKind::Sawtooth;
        } else if (p == "sine") {
            c.kind = AirborneKind::Sine;
        } else if (p == "polygon") {
            c.kind = AirborneKind::Polygon;
        } else if (p == "palmer") {
            c.kind = AirborneKind::Palmer;
        } else {
            r.fail("airborne.pattern", "'" + p + "' is not sawtooth, sine, polygon or palmer");
        }
    }
    if (n["prf_khz"]) c.prf_hz = 1e3 * r.number(n["prf_khz"], "airborne.prf_khz", 0, 10000, true);
    if (n["scan_rate_hz"])
        c.scan_rate_hz = r.number(n["scan_rate_hz"], "airborne.scan_rate_hz", 0, 2000, true);
    if (n["fov_deg"]) c.fov_deg = r.number(n["fov_deg"], "airborne.fov_deg", 0, 180, true, true);
    if (n["tilt_deg"]) c.tilt_deg = r.number(n["tilt_deg"], "airborne.tilt_deg", -60, 60);
    if (n["facets"]) {
        if (c.kind != AirborneKind::Polygon)
            r.fail("airborne.facets",
                   "only for pattern polygon (pattern is " + to_string(c.kind) + ")");
        c.facets = static_cast<int>(r.integer(n["facets"], "airborne.facets", 1, 64));
    }
    if (c.kind != AirborneKind::Polygon) c.facets = 1;
    if (c.lines_per_s() > c.prf_hz / 2)
        r.fail("airborne.scan_rate_hz", num(c.scan_rate_hz) +
                                            " Hz leaves fewer than 2 pulses per line at " +
                                            num(c.prf_hz * 1e-3) + " kHz");
    return make_airborne_pattern(c);
}

// `path` labels errors and gives the default name; `text` as in Reader::load.
SensorModel read_sensor(const std::string& path, const std::string* text) {
    const Reader r(path);
    const YAML::Node root = r.load(text);
    if (!root.IsMap()) r.fail("", "expected a mapping with 'base' and/or sensor sections");
    r.only_keys(root, "",
                {"base", "name", "beam", "receiver", "noise", "detector", "spinning", "airborne",
                 "array", "point_source_id"});

    SensorModel m;
    std::string base_name;
    if (root["base"]) {
        base_name = r.text(root["base"], "base");
        const auto names = preset_names();
        if (std::find(names.begin(), names.end(), base_name) == names.end()) {
            std::string list;
            for (const auto& nm : names) list += (list.empty() ? "" : ", ") + nm;
            r.fail("base", "unknown preset '" + base_name + "' (known: " + list + ")");
        }
        m = preset(base_name);
        unmake_array(m);  // an array preset: the file's keys apply to the laser, then it is made
    } else if (!root["spinning"] && !root["airborne"]) {
        r.fail("", "needs 'base: <preset>' or a 'spinning' or 'airborne' section");
    } else if (root["spinning"] && root["airborne"]) {
        r.fail("airborne", "a sensor is either spinning or airborne, not both");
    }
    m.name =
        root["name"] ? r.text(root["name"], "name") : std::filesystem::path(path).stem().string();

    if (root["beam"]) read_beam(r, root["beam"], m.beam);
    if (root["receiver"]) read_receiver(r, root["receiver"], m.receiver);
    if (root["noise"]) read_noise(r, root["noise"], m.noise);
    if (root["detector"]) read_detector(r, root["detector"], m);
    if (root["noise"] && m.detector == DetectorKind::Geiger)
        r.fail("noise", "a Geiger-mode detector times its events itself (detector.jitter_ns)");
    // A range gate shorter than the pulse could hold no echo (docs/time-resolved.md §9).
    const double gate_ns = 2e9 * (m.receiver.max_range_m - m.receiver.min_range_m) / 299'792'458.0;
    if (gate_ns < m.beam.pulse_width_s * 1e9)
        r.fail(root["receiver"] ? "receiver.max_range_m" : "beam.pulse_width_ns",
               "the range gate (" + num(gate_ns) + " ns two-way) is shorter than the pulse (" +
                   num(m.beam.pulse_width_s * 1e9) + " ns)");
    // The void rule belongs to the discrete detector; the others decide by their own physics.
    if (m.detector != DetectorKind::Discrete && root["receiver"])
        for (const char* key : {"threshold_gamma", "noise_irradiance_sigma"})
            if (root["receiver"][key])
                r.fail(join_path("receiver", key),
                       "the discrete detector's void rule: the linear detector has "
                       "detector.threshold_counts and detector.thermal_noise_pe, the Geiger one "
                       "its photon statistics");

    if (root["spinning"]) {
        const auto* base = dynamic_cast<const SpinningPattern*>(m.scan.get());
        if (m.scan && !base)
            r.fail("spinning", "base '" + base_name + "' is " + what_scan(*m.scan));
        const std::uint32_t base_channels = base ? base->channels() : 0;
        m.scan = read_spinning(r, root["spinning"], base, base_name);
        m.airborne = false;
        // The vendor's packets have a fixed number of channels: another laser table has none.
        if (m.scan->channels() != base_channels) m.wire = {};
    }
    if (root["airborne"]) {
        const auto* base = dynamic_cast<const AirbornePattern*>(m.scan.get());
        if (m.scan && !base)
            r.fail("airborne", "base '" + base_name + "' is " + what_scan(*m.scan));
        m.scan = read_airborne(r, root["airborne"], base);
        m.airborne = true;
    }
    if (root["point_source_id"])
        m.point_source_id = static_cast<std::uint16_t>(
            r.integer(root["point_source_id"], "point_source_id", 0, 65535));
    finish_array(r, root, m);
    check_geiger_timing(r, m);
    if (m.geiger.crosstalk_probability > 0.0 && !m.array.on())
        r.fail("detector.crosstalk_probability", "crosstalk needs neighbours: an array");
    return m;
}

}  // namespace

SensorModel load_sensor_yaml(const std::string& path) { return read_sensor(path, nullptr); }

SensorModel load_sensor_yaml_text(const std::string& yaml, const std::string& name) {
    return read_sensor(name, &yaml);
}

SensorModel resolve_sensor(const std::string& spec) {
    const auto names = preset_names();
    if (std::find(names.begin(), names.end(), spec) != names.end()) return preset(spec);
    if (std::filesystem::is_regular_file(spec)) return load_sensor_yaml(spec);
    std::string list;
    for (const auto& nm : names) list += (list.empty() ? "" : ", ") + nm;
    throw ConfigError("sensor '" + spec + "': neither a preset (" + list + ") nor a YAML file");
}

}  // namespace mirage::sensor
