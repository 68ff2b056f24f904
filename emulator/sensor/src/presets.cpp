// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/presets.hpp"

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "calibration_tables.hpp"
#include "mirage/core/error.hpp"
#include "mirage/sensor/airborne.hpp"
#include "mirage/sensor/array.hpp"
#include "mirage/sensor/spinning.hpp"
#include "mirage/sensor/staring.hpp"
#include "ouster_presets.hpp"

namespace mirage::sensor {
namespace {

constexpr double kPlanckJs = 6.62607015e-34;
constexpr double kLightMps = 299'792'458.0;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kNoiseFloorElectrons = 10.0;  // detector floor per unit normal (eq. 12)

// The µs tables give whole ns; snap so 55.296 µs becomes exactly 55 296 ns.
double us_to_ns(double us) {
    const double ns = us * 1000.0;
    const double r = std::round(ns);
    return std::abs(ns - r) < 1e-6 ? r : ns;
}

struct Optics {
    double wavelength_nm;
    double energy_uj;
    double pulse_width_ns;
    double divergence_mrad;
    double laser_bandwidth_nm;
    double aperture_mm;
    double f_number;
    double quantum_efficiency;
    double filter_nm;
    double min_range_m;
    double max_range_m;
    double range_resolution_m;
    int max_returns;
    double range_sigma_m;
    double jitter_sigma_mrad;
};

// Fills beam, receiver and noise; the pixel IFOV is twice the beam divergence so the spot fits
// with alignment margin, and σ₁ gives a 10 e⁻ noise floor.
void apply_optics(const Optics& o, SensorModel& m) {
    m.beam.wavelength_m = o.wavelength_nm * 1e-9;
    m.beam.pulse_energy_j = o.energy_uj * 1e-6;
    m.beam.pulse_width_s = o.pulse_width_ns * 1e-9;
    m.beam.divergence_rad = o.divergence_mrad * 1e-3;
    m.beam.laser_bandwidth_m = o.laser_bandwidth_nm * 1e-9;
    m.beam.profile = BeamProfile::Gaussian;
    m.beam.sub_rays = 1;
    m.receiver.aperture_diameter_m = o.aperture_mm * 1e-3;
    m.receiver.f_number = o.f_number;
    m.receiver.detector_area_m2 = detector_area_for_ifov(
        2.0 * m.beam.divergence_rad, m.receiver.aperture_diameter_m, o.f_number);
    m.receiver.eta_transmitter = 0.9;
    m.receiver.eta_receiver = 0.8;
    m.receiver.quantum_efficiency = o.quantum_efficiency;
    m.receiver.detector_bandwidth_m = o.filter_nm * 1e-9;
    m.receiver.integration_time_s = 0;  // = pulse width
    m.receiver.threshold_gamma = 3.0;
    m.receiver.min_range_m = o.min_range_m;
    m.receiver.max_range_m = o.max_range_m;
    m.receiver.range_resolution_m = o.range_resolution_m;
    m.receiver.max_returns = o.max_returns;
    m.receiver.noise_irradiance_sigma =
        noise_sigma_for_floor(kNoiseFloorElectrons, m.beam, m.receiver);
    m.noise.range_sigma_m = o.range_sigma_m;
    m.noise.jitter_sigma_rad = o.jitter_sigma_mrad * 1e-3;
}

// Pulse energies below: chosen so a 10 % Lambertian target at max range, normal incidence, no
// atmosphere, gives a few hundred photo-electrons with
//   N = E·η_t·η_r·ρ·A_r/(πR²)·λη/(hc),  A_r = π(D/2)², η_t·η_r = 0.72, hc = 1.98645e-25 J·m.
// (= radiometry.hpp's P_peak·η_t·η_r·τ²·ρ·cos θ·A_r/(πR²) times pulse width times λη/(hc)).

// 905 nm Si APD: 0.1 µJ, D = 25 mm, R = 100 m, η = 0.7:
//   0.1e-6·0.72·0.1·4.909e-4/(π·1e4)·905e-9·0.7/1.98645e-25 = 359 e⁻  (peak power 20 W).
Optics vlp16_optics() {
    return {905, 0.10, 5, 3.0, 5, 25, 1.0, 0.7, 20, 0.5, 100, 0.002, 1, 0.03, 0.05};
}
// HDL-32E: same optics, 2.8 mrad; 359 e⁻ at 100 m.
Optics hdl32e_optics() {
    return {905, 0.10, 5, 2.8, 5, 25, 1.0, 0.7, 20, 1.0, 100, 0.002, 1, 0.02, 0.05};
}
// VLP-32C: 0.4 µJ, D = 25 mm, R = 200 m → 0.4e-6·0.72·0.1·4.909e-4/(π·4e4)·3.189e18 = 359 e⁻.
Optics vlp32c_optics() {
    return {905, 0.40, 5, 3.0, 5, 25, 1.0, 0.7, 20, 1.0, 200, 0.004, 1, 0.03, 0.05};
}
// HDL-64E S3: 0.12 µJ, D = 30 mm (A_r = 7.069e-4), R = 120 m:
//   0.12e-6·0.72·0.1·7.069e-4/(π·14400)·3.189e18 = 431 e⁻.
Optics hdl64e_optics() {
    return {905, 0.12, 5, 2.0, 5, 30, 1.0, 0.7, 20, 0.9, 120, 0.002, 1, 0.02, 0.05};
}
// OS1: 865 nm SPAD, photon detection efficiency ≈ 0.25; 0.5 µJ, D = 25 mm, R = 120 m:
//   0.5e-6·0.72·0.1·4.909e-4/(π·14400)·865e-9·0.25/1.98645e-25 = 425 e⁻.
// OS0 (R = 50 m) and OS2 (R = 240 m) scale the energy with R² for the same 425 e⁻:
//   0.5·(50/120)² = 0.087 µJ, 0.5·(240/120)² = 2.0 µJ.
Optics os1_optics() {
    return {865, 0.50, 5, 3.0, 5, 25, 1.0, 0.25, 20, 0.5, 120, 0.001, 1, 0.03, 0.05};
}
Optics os0_optics() {
    return {865, 0.087, 5, 3.0, 5, 25, 1.0, 0.25, 20, 0.3, 50, 0.001, 1, 0.03, 0.05};
}
Optics os2_optics() {
    return {865, 2.0, 5, 3.0, 5, 25, 1.0, 0.25, 20, 0.5, 240, 0.001, 1, 0.03, 0.05};
}
// Airborne, 1064 nm, Si APD η = 0.4, D = 80 mm (A_r = 5.027e-3), 5 µJ, R = 2000 m:
//   5e-6·0.72·0.1·5.027e-3/(π·4e6)·1064e-9·0.4/1.98645e-25 = 309 e⁻  (2.5 W mean at 500 kHz).
Optics als_optics() {
    return {1064, 5.0, 4, 0.5, 0.5, 80, 2.0, 0.4, 3, 10, 2000, 0.0, 4, 0.02, 0.05};
}

SensorModel spinning_model(const std::string& name, SpinningConfig cfg, const Optics& o) {
    SensorModel m;
    m.name = name;
    m.scan = std::make_shared<SpinningPattern>(std::move(cfg));
    m.airborne = false;
    m.point_source_id = 1;
    apply_optics(o, m);
    return m;
}

SpinningConfig velodyne_config(double period_us) {
    SpinningConfig c;
    c.sequence_period_ns = us_to_ns(period_us);
    c.rotation_hz = 600.0 / 60.0;  // 600 rpm default
    c.family = SpinningFamily::Velodyne;
    return c;
}

// VLP-16 / Hi-Res: 16 firings 2.304 µs apart, 55.296 µs sequence (docs/wire-formats.md §1.4).
SensorModel make_vlp16(const std::string& name, const std::array<double, 16>& elevations) {
    SpinningConfig c = velodyne_config(55.296);
    for (std::size_t i = 0; i < elevations.size(); ++i)
        c.lasers.push_back({elevations[i], 0.0, us_to_ns(2.304 * double(i))});
    return spinning_model(name, std::move(c), vlp16_optics());
}

// VLP-32C: pairs (2k, 2k+1) at 2.304·k µs, 55.296 µs sequence, azimuth offsets δ = −ρ.
SensorModel make_vlp32c() {
    SpinningConfig c = velodyne_config(55.296);
    for (std::size_t i = 0; i < tables::kVlp32c.size(); ++i)
        c.lasers.push_back({tables::kVlp32c[i].elevation_deg, tables::kVlp32c[i].azimuth_deg,
                            us_to_ns(2.304 * double(i / 2))});
    return spinning_model("vlp32c", std::move(c), vlp32c_optics());
}

// HDL-32E: 1.152 µs per laser, 46.08 µs sequence.
SensorModel make_hdl32e() {
    SpinningConfig c = velodyne_config(46.08);
    for (std::size_t i = 0; i < tables::kHdl32eElevationDeg.size(); ++i)
        c.lasers.push_back({tables::kHdl32eElevationDeg[i], 0.0, us_to_ns(1.152 * double(i))});
    return spinning_model("hdl32e", std::move(c), hdl32e_optics());
}

// HDL-64E S3: 64 lasers per 48 µs cycle; the upper laser u and the lower laser 32 + u fire
// together. VeloView places slot c at T[rc mod 4] + 6·⌊rc/4⌋ µs before the timestamp with
// rc = 31 − c, T = {2.34, 3.54, 4.74, 6.0} (docs/wire-formats.md §1.6); measured from the first
// firing of the cycle that is 6·⌊u/4⌋ + (6 − T[3 − u mod 4]) = 6·⌊u/4⌋ + {0, 1.26, 2.46, 3.66}.
SensorModel make_hdl64e_s3() {
    SpinningConfig c = velodyne_config(48.0);
    constexpr std::array<double, 4> kT = {2.34, 3.54, 4.74, 6.0};
    for (std::size_t l = 0; l < tables::kHdl64eS3Xiesc.size(); ++l) {
        const std::size_t u = l % 32;
        const double offset_us = 6.0 * double(u / 4) + (6.0 - kT[3 - u % 4]);
        const auto& cal = tables::kHdl64eS3Xiesc[l];
        c.lasers.push_back({cal.vert_rad / kDeg, -cal.rot_rad / kDeg, us_to_ns(offset_us)});
    }
    return spinning_model("hdl64e-s3", std::move(c), hdl64e_optics());
}

// Ouster OS0/OS1/OS2 (beam tables and timing in ouster_presets.cpp).
SensorModel make_ouster(const std::string& name, const detail::OusterPresetSpec& spec) {
    const Optics o = spec.product == 0   ? os0_optics()
                     : spec.product == 1 ? os1_optics()
                                         : os2_optics();
    return spinning_model(name, detail::ouster_spinning_config(spec), o);
}

SensorModel airborne_model(const std::string& name, const AirborneConfig& cfg) {
    SensorModel m;
    m.name = name;
    m.scan = make_airborne_pattern(cfg);
    m.airborne = true;
    m.point_source_id = 1;
    apply_optics(als_optics(), m);
    return m;
}

AirborneConfig als_config(AirborneKind kind, double prf_khz, double rate_hz, double fov_deg,
                          int facets = 1) {
    AirborneConfig c;
    c.kind = kind;
    c.prf_hz = prf_khz * 1e3;
    c.scan_rate_hz = rate_hz;
    c.fov_deg = fov_deg;
    c.facets = facets;
    return c;
}

// A full-waveform airborne scanner (docs/sensors.md §1): als-mirror's 1064 nm optics and scan,
// 19 sub-rays, a 4 ns pulse and a 1 GS/s, 14-bit digitiser behind a silicon APD. The gain keeps
// a 30 % target at 200 m (2·10⁴ photo-electrons in the peak sample) inside full scale.
SensorModel als_waveform() {
    SensorModel m = airborne_model("als-waveform", als_config(AirborneKind::Sawtooth, 500, 50, 40));
    m.beam.sub_rays = 19;
    m.detector = DetectorKind::Linear;
    m.linear.sample_rate_gsps = 1.0;
    m.linear.bits = 14;
    m.linear.offset_counts = 200;
    m.linear.gain_counts_per_pe = 0.5;
    m.linear.apd_gain = 100;
    m.linear.apd_k = 0.02;
    m.linear.thermal_noise_pe = 3;
    m.linear.dark_current_na = 1;
    return m;
}

// An airborne Geiger-mode flash array, ALIRT-like (docs/photon-counting.md §3 gives each value's
// source): a 32 × 32 array on a 15° sinusoidal whisk broom at 780 nm, gated for ~1 200 m.
// Puts a columns × rows array of `pitch_m` pixels behind a `focal_m` lens on the preset's laser.
void put_array(SensorModel& m, std::uint32_t columns, std::uint32_t rows, double pitch_m,
               double focal_m, double fill_factor) {
    m.array.columns = columns;
    m.array.rows = rows;
    m.array.pitch_m = pitch_m;
    m.array.focal_length_m = focal_m;
    m.array.fill_factor = fill_factor;
    make_array(m, "preset '" + m.name + "'");
}

SensorModel gmapd_32x32() {
    AirborneConfig c = als_config(AirborneKind::Sine, 20, 10, 15);
    SensorModel m = airborne_model("gmapd-32x32", c);
    m.beam.wavelength_m = 780e-9;
    m.beam.pulse_energy_j = 5e-6;
    m.beam.pulse_width_s = 1e-9;
    m.beam.divergence_rad = 2.5e-3;  // the flash over the array's 2 mrad field
    m.beam.profile = BeamProfile::Gaussian;
    m.beam.sub_rays = 1;
    m.receiver.aperture_diameter_m = 0.1;
    m.receiver.detector_bandwidth_m = 1e-9;
    m.receiver.min_range_m = 1100;
    m.receiver.max_range_m = 1400;
    m.receiver.quantum_efficiency = 0.3;  // the PDE
    m.noise = {};                         // the detector's timing is its own
    m.detector = DetectorKind::Geiger;
    m.geiger.bin_ns = 0.25;
    m.geiger.dark_count_rate_hz = 5e3;
    m.geiger.dead_time_ns = 2000;  // ≥ the gate: framed, one event per pixel and gate
    m.geiger.jitter_ns = 0.24;
    m.geiger.crosstalk_probability = 0.02;
    put_array(m, 32, 32, 50e-6, 0.8, 0.7);
    return m;
}

// A flash frame staring along `nadir` or forward: the laser at `frame_hz` behind the array, every
// pixel-pulse one frame's pixel (docs/photon-counting.md §3).
SensorModel flash_frame(const std::string& name, const Optics& o, bool nadir, double frame_hz) {
    SensorModel m;
    m.name = name;
    m.scan = std::make_shared<StaringPattern>(frame_hz, nadir);
    m.airborne = nadir;
    m.point_source_id = 1;
    apply_optics(o, m);
    m.beam.profile = BeamProfile::TopHat;  // shaped to the array's field: 1/N per pixel
    m.beam.sub_rays = 1;
    return m;
}

// NVIG-like (the second seed): a 320 × 240 frame at 10 Hz looking down, 1064 nm, the seed's
// discrete detection (void rule, range noise, jitter). 50 µm pixels behind a 45.4 mm f/1.4 lens:
// 1.10 mrad, a 20° × 15° field (176 × 132 m from 500 m). 200 mJ flashes: a 10 % surface at 500 m
// gives each pixel a few hundred e⁻ (docs/photon-counting.md §3).
SensorModel nvig_320x240() {
    Optics o = als_optics();
    o.energy_uj = 200e3;
    o.aperture_mm = 32;
    o.min_range_m = 50;
    o.max_range_m = 3000;
    SensorModel m = flash_frame("nvig-320x240", o, true, 10);
    put_array(m, 320, 240, 50e-6, 45.37e-3, 0.8);
    return m;
}

// An automotive flash lidar (illustrative, of the class of 128 × 32-pixel, 25 Hz flash units):
// looking forward, 905 nm, 93 µm pixels behind a 5 mm f/1.2 lens: 18.6 mrad pixels, a 100° × 33°
// field; 1 mJ flashes of 5 ns, so a 10 % target at 30 m gives each pixel a few hundred e⁻
// (docs/photon-counting.md §3); discrete detection with the VLP-16's noise.
SensorModel automotive_flash_128x32() {
    Optics o = vlp16_optics();
    o.energy_uj = 1000;
    o.aperture_mm = 4.2;
    o.min_range_m = 0.5;
    o.max_range_m = 150;
    SensorModel m = flash_frame("flash-128x32", o, false, 25);
    put_array(m, 128, 32, 93e-6, 5e-3, 0.6);
    return m;
}

}  // namespace

double detector_area_for_ifov(double ifov_rad, double aperture_diameter_m, double f_number) {
    const double d = ifov_rad * f_number * aperture_diameter_m;  // pixel diameter at the focus
    return std::numbers::pi * 0.25 * d * d;
}

double ifov_rad(const ReceiverParams& rx) {
    const double pixel_d = std::sqrt(4.0 * rx.detector_area_m2 / std::numbers::pi);
    return pixel_d / (rx.f_number * rx.aperture_diameter_m);
}

double noise_sigma_for_floor(double electrons, const BeamParams& beam, const ReceiverParams& rx) {
    const double tau = rx.integration_time_s > 0 ? rx.integration_time_s : beam.pulse_width_s;
    const double band_um = rx.detector_bandwidth_m * 1e6;
    const double per_sigma = tau * beam.wavelength_m * band_um * rx.detector_area_m2 *
                             rx.quantum_efficiency / (kPlanckJs * kLightMps);
    return per_sigma > 0 ? electrons / per_sigma : 0.0;
}

double lambertian_electrons(const BeamParams& beam, const ReceiverParams& rx, double reflectance,
                            double range_m) {
    const double area = std::numbers::pi * 0.25 * rx.aperture_diameter_m * rx.aperture_diameter_m;
    const double energy = beam.pulse_energy_j * rx.eta_transmitter * rx.eta_receiver * reflectance *
                          area / (std::numbers::pi * range_m * range_m);
    return energy * beam.wavelength_m * rx.quantum_efficiency / (kPlanckJs * kLightMps);
}

std::vector<std::string> preset_names() {
    std::vector<std::string> names = {"vlp16", "vlp16-hires", "vlp32c", "hdl32e", "hdl64e-s3"};
    for (auto& n : detail::ouster_preset_names()) names.push_back(std::move(n));
    for (const char* n : {"als-mirror", "als-mirror-sine", "als-polygon", "als-palmer",
                          "als-waveform", "gmapd-32x32", "nvig-320x240", "flash-128x32"})
        names.emplace_back(n);
    return names;
}

namespace {

SensorModel with_wire(SensorModel m, WireFamily family) {
    m.wire = {family, m.name};
    return m;
}

}  // namespace

SensorModel preset(const std::string& name) {
    const auto velodyne = WireFamily::Velodyne;
    if (name == "vlp16") return with_wire(make_vlp16(name, tables::kVlp16ElevationDeg), velodyne);
    if (name == "vlp16-hires")
        return with_wire(make_vlp16(name, tables::kVlp16HiResElevationDeg), velodyne);
    if (name == "vlp32c") return with_wire(make_vlp32c(), velodyne);
    if (name == "hdl32e") return with_wire(make_hdl32e(), velodyne);
    if (name == "hdl64e-s3") return with_wire(make_hdl64e_s3(), velodyne);
    if (detail::OusterPresetSpec os; detail::parse_ouster_preset(name, os))
        return with_wire(make_ouster(name, os), WireFamily::Ouster);
    // Oscillating mirror: 50 Hz = 100 lines/s, ±20°, 500 kHz (docs/physics.md §4.1 airborne
    // pattern).
    if (name == "als-mirror")
        return airborne_model(name, als_config(AirborneKind::Sawtooth, 500, 50, 40));
    if (name == "als-mirror-sine")
        return airborne_model(name, als_config(AirborneKind::Sine, 500, 50, 40));
    // Rotating polygon, 4 facets × 50 rev/s = 200 lines/s over 60°, 1 MHz.
    if (name == "als-polygon")
        return airborne_model(name, als_config(AirborneKind::Polygon, 1000, 50, 60, 4));
    // Palmer cone of half-angle 20°, 50 rev/s (100 lines/s, forward and backward), 1 MHz.
    if (name == "als-palmer")
        return airborne_model(name, als_config(AirborneKind::Palmer, 1000, 50, 40));
    if (name == "als-waveform") return als_waveform();
    if (name == "gmapd-32x32") return gmapd_32x32();
    if (name == "nvig-320x240") return nvig_320x240();
    if (name == "flash-128x32") return automotive_flash_128x32();
    std::string known;
    for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
    throw ConfigError("sensor: unknown preset '" + name + "' (known: " + known + ")");
}

}  // namespace mirage::sensor
