// SPDX-License-Identifier: Apache-2.0
// Start-up print of the effective sensor configuration. Beam and receiver settings are resolved
// once per sensor and shared by all channels; the per-channel table repeats them so a reader can
// see every override reach every channel (docs/physics.md §3.5).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "mirage/sensor/airborne.hpp"
#include "mirage/sensor/array.hpp"
#include "mirage/sensor/presets.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/sensor/spinning.hpp"
#include "mirage/sensor/staring.hpp"

namespace mirage::sensor {
namespace {

std::string timing_text(const LinearDetectorParams& d) {
    switch (d.timing) {
        case EchoTiming::ConstantFraction:
            return fmt::format("constant fraction {:.2f} of the amplitude", d.cfd_fraction);
        case EchoTiming::Decomposition:
            return "Gaussian decomposition";
        case EchoTiming::Peak:
            break;
    }
    return "peak (Gaussian fit; matched filter for a measured pulse)";
}

std::string channel_tail(const SensorModel& m) {
    return fmt::format(" | {:.1f} nm {:.3f} uJ {:.3f} mrad sub-rays {} range {:.2f}-{:.1f} m",
                       m.beam.wavelength_m * 1e9, m.beam.pulse_energy_j * 1e6,
                       m.beam.divergence_rad * 1e3, m.beam.sub_rays, m.receiver.min_range_m,
                       m.receiver.max_range_m);
}

std::string array_text(const ArrayParams& a, double pixel_pulses_per_s) {
    const bool flash = a.illumination == Illumination::Flash;
    std::string laser;
    if (flash)
        laser = fmt::format(", laser {:.3f} mrad {}", a.laser_divergence_rad * 1e3,
                            a.laser_profile == BeamProfile::Gaussian ? "gaussian" : "tophat");
    float lo = 1, hi = 0;
    for (float s : a.share) lo = std::min(lo, s), hi = std::max(hi, s);
    return fmt::format(
        "  array: {} x {} pixels, pitch {:.1f} um, focal length {:.1f} mm (IFOV {:.4f} mrad), "
        "fill {:.2f}, {}{}; pixel share of the pulse {:.4g}-{:.4g}; {:.0f} pixel-pulses/s; the "
        "beam and receiver below are a pixel's\n",
        a.columns, a.rows, a.pitch_m * 1e6, a.focal_length_m * 1e3, a.ifov_rad() * 1e3,
        a.fill_factor, flash ? "flash" : "beamlets", laser, lo, hi, pixel_pulses_per_s);
}

}  // namespace

std::string describe(const SensorModel& m) {
    const BeamParams& b = m.beam;
    const ReceiverParams& rx = m.receiver;
    std::string out;
    // An array rides the laser's own pattern.
    const auto* array = dynamic_cast<const ArrayScan*>(m.scan.get());
    const ScanPattern* laser = array ? &array->laser() : m.scan.get();
    const auto* spin = dynamic_cast<const SpinningPattern*>(laser);
    const auto* air = dynamic_cast<const AirbornePattern*>(laser);
    if (m.scan) {
        out += fmt::format("sensor '{}': {}, {} channel(s), {:.0f} pulses/s, group {}\n", m.name,
                           m.scan->kind(), m.scan->channels(), m.scan->pulse_rate_hz(),
                           m.scan->group_size());
    } else {
        out += fmt::format("sensor '{}': no scan pattern\n", m.name);
    }
    if (spin) {
        const auto& c = spin->config();
        out += fmt::format(
            "  scan: {:.1f} rpm ({:.3f} Hz), sequence {:.3f} us, azimuth step {:.5f} deg\n",
            spin->rpm(), c.rotation_hz, c.sequence_period_ns * 1e-3, spin->azimuth_step_deg());
    }
    if (air) {
        const auto& c = air->config();
        out += fmt::format(
            "  scan: {} {:.1f} kHz, scan rate {:.2f} Hz ({:.1f} lines/s), fov {:.2f} deg, "
            "facets {}, tilt {:.2f} deg\n",
            to_string(c.kind), c.prf_hz * 1e-3, c.scan_rate_hz, c.lines_per_s(), c.fov_deg,
            c.facets, c.tilt_deg);
    }
    if (const auto* stare = dynamic_cast<const StaringPattern*>(laser))
        out += fmt::format("  scan: staring {}, {:.3f} Hz (a frame per pulse)\n",
                           stare->nadir() ? "down" : "forward", stare->pulse_rate_hz());
    if (m.array.on()) out += array_text(m.array, m.scan->pulse_rate_hz());
    out += fmt::format(
        "  beam: {:.1f} nm, {:.4f} uJ, {:.2f} ns (peak {:.1f} W), divergence {:.3f} mrad {}, "
        "sub-rays {}, laser bandwidth {:.2f} nm\n",
        b.wavelength_m * 1e9, b.pulse_energy_j * 1e6, b.pulse_width_s * 1e9,
        b.pulse_width_s > 0 ? b.pulse_energy_j / b.pulse_width_s : 0.0, b.divergence_rad * 1e3,
        b.profile == BeamProfile::Gaussian ? "gaussian" : "tophat", b.sub_rays,
        b.laser_bandwidth_m * 1e9);
    if (!b.pulse_t_ns.empty())
        out += fmt::format("  pulse: measured shape from '{}', {} samples, FWHM {:.3f} ns\n",
                           b.pulse_shape_file, b.pulse_t_ns.size(), b.pulse_width_s * 1e9);
    if (b.footprint_radius != 1.0)
        out += fmt::format("  footprint: sub-rays out to {:.2f} 1/e^2 radii\n", b.footprint_radius);
    if (b.adaptive_footprint)
        out += "  footprint: adaptive (probes first; one plane in closed form)\n";
    const double ifov = ifov_rad(rx);
    const double per_sigma = noise_sigma_for_floor(1.0, b, rx);
    out += fmt::format(
        "  receiver: aperture {:.2f} mm f/{:.2f}, detector {:.5f} mm2 (IFOV {:.2f} mrad), "
        "eta_t {:.2f}, eta_r {:.2f}, QE {:.2f}, filter {:.2f} nm, t_int {:.2f} ns, "
        "sigma1 {:.4g} W/(m2 um) (floor {:.1f} e-), gamma {:.2f}, range {:.2f}-{:.1f} m, "
        "resolution {:.4f} m, max returns {}\n",
        rx.aperture_diameter_m * 1e3, rx.f_number, rx.detector_area_m2 * 1e6, ifov * 1e3,
        rx.eta_transmitter, rx.eta_receiver, rx.quantum_efficiency, rx.detector_bandwidth_m * 1e9,
        (rx.integration_time_s > 0 ? rx.integration_time_s : b.pulse_width_s) * 1e9,
        rx.noise_irradiance_sigma, per_sigma > 0 ? rx.noise_irradiance_sigma / per_sigma : 0.0,
        rx.threshold_gamma, rx.min_range_m, rx.max_range_m, rx.range_resolution_m, rx.max_returns);
    if (m.array.on()) {  // a pixel takes its share of the pulse and its fill factor of the light
        float top = 0;
        for (float s : m.array.share) top = std::max(top, s);
        out += fmt::format(
            "  link: 10% Lambertian at {:.1f} m -> {:.3g} photo-electrons in the brightest pixel\n",
            rx.max_range_m,
            double(top) * m.array.fill_factor * lambertian_electrons(b, rx, 0.1, rx.max_range_m));
    } else {
        out += fmt::format("  link: 10% Lambertian at {:.1f} m -> {:.0f} photo-electrons\n",
                           rx.max_range_m, lambertian_electrons(b, rx, 0.1, rx.max_range_m));
    }
    if (rx.speckle_cells != 0)
        out += fmt::format("  speckle: {:.1f} cells{} (contrast {:.3f})\n", speckle_cells(m),
                           rx.speckle_cells == kSpeckleAuto ? " from aperture and spot" : "",
                           1 / std::sqrt(speckle_cells(m)));
    if (rx.diffuse_bounces > 0)
        out += fmt::format("  paths: up to {} diffuse bounces, seen within the IFOV\n",
                           rx.diffuse_bounces);
    out += fmt::format("  noise: range sigma {:.4f} m, jitter sigma {:.4f} mrad\n",
                       m.noise.range_sigma_m, m.noise.jitter_sigma_rad * 1e3);
    if (m.detector == DetectorKind::Linear) {
        const LinearDetectorParams& d = m.linear;
        out += fmt::format(
            "  detector: linear, pulse FWHM {:.3f} ns, digitiser {:.3f} GS/s {} bits "
            "offset {:.1f} counts, gain {:.3f} counts/pe, APD M {:.1f} k {:.3f}, thermal {:.2f} "
            "pe rms, dark {:.3f} nA, threshold {}\n",
            b.pulse_width_s * 1e9, d.sample_rate_gsps, d.bits, d.offset_counts,
            d.gain_counts_per_pe, d.apd_gain, d.apd_k, d.thermal_noise_pe, d.dark_current_na,
            d.threshold_counts > 0 ? fmt::format("{:.1f} counts", d.threshold_counts)
                                   : std::string("4 sigma of the noise floor"));
        out += "  echo timing: " + timing_text(d) + "\n";
    } else if (m.detector == DetectorKind::Geiger) {
        const GeigerDetectorParams& d = m.geiger;
        out += fmt::format(
            "  detector: Geiger-mode, PDE {:.3f}, gate {:.1f}-{:.1f} ns in {:.3f} ns bins, dark "
            "{:.3f} kHz, dead time {:.1f} ns ({}), jitter {:.3f} ns, afterpulses {:.4f} after "
            "{:.1f} ns, up to {} event(s) per gate, {}\n",
            rx.quantum_efficiency, 2e9 * rx.min_range_m / 299'792'458.0,
            2e9 * rx.max_range_m / 299'792'458.0, d.bin_ns, d.dark_count_rate_hz * 1e-3,
            d.dead_time_ns, d.paralyzable ? "paralyzable" : "non-paralyzable", d.jitter_ns,
            d.afterpulse_probability, d.afterpulse_delay_ns, d.max_events,
            d.free_running ? "free-running (dead time carried across pulses)" : "gated");
    } else {
        out += "  detector: discrete (sub-ray hits merged c*tau/2 apart)\n";
    }
    out += fmt::format("  LAS: point source id {}, scan angle = {}\n", m.point_source_id,
                       m.airborne ? "across-track angle (+ right)" : "elevation");
    const std::string tail = channel_tail(m);
    if (spin) {
        const auto& lasers = spin->config().lasers;
        for (std::size_t i = 0; i < lasers.size(); ++i)
            out +=
                fmt::format("  ch {:3d}: elev {:8.3f} deg, az {:+7.3f} deg, fires {:7.3f} us{}\n",
                            i, lasers[i].elevation_deg, lasers[i].azimuth_offset_deg,
                            lasers[i].firing_offset_ns * 1e-3, tail);
    } else if (m.scan) {
        for (std::uint32_t i = 0; i < m.scan->channels(); ++i)
            out += fmt::format("  ch {:3d}:{}\n", i, tail);
    }
    return out;
}

}  // namespace mirage::sensor
