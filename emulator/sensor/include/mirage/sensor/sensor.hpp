// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mirage/core/time.hpp"

namespace mirage::sensor {

enum class BeamProfile { Gaussian, TopHat };

// Transmitter. SI units throughout.
struct BeamParams {
    double wavelength_m = 905e-9;
    double laser_bandwidth_m = 5e-9;
    double pulse_energy_j = 1e-7;  // per pulse
    double pulse_width_s = 5e-9;   // FWHM
    double divergence_rad = 3e-3;  // full angle (1/e² diameter for Gaussian)
    BeamProfile profile = BeamProfile::Gaussian;
    int sub_rays = 1;  // footprint samples per pulse: 1, 7, 19, 37, ... (hex rings)
    // Radius the sub-rays reach, in 1/e² radii (Gaussian profile only): 1 drops the 13.5 % of
    // the energy outside it, 2 keeps all but 0.03 % (docs/physics.md §3.5).
    double footprint_radius = 1.0;
    // Adaptive footprints (docs/physics.md §2.9): a few probe sub-rays first; a pulse whose probes
    // agree on one plane takes its footprint integral in closed form, the others trace the rest.
    bool adaptive_footprint = false;
    // Pulse-to-pulse energy variation: each pulse fires E·max(0, 1 + σ·z), z standard normal
    // drawn per pulse (docs/time-resolved.md §6); 0: every pulse the same.
    double energy_sigma = 0.0;
    // The pulse in time (docs/time-resolved.md §4): a Gaussian whose FWHM is pulse_width_s, or
    // this measured shape (time ns, relative power; pulse_width_s is then its FWHM).
    std::vector<double> pulse_t_ns, pulse_power;
    std::string pulse_shape_file;  // where the measured shape came from, for summaries
};

// The most returns a pulse reports (the renderer separates at most this many surfaces).
inline constexpr int kMaxReturns = 8;

// Receiver and detector (docs/physics.md eqs. (4)–(13)).
inline constexpr int kMaxPathDepth = 8;

struct ReceiverParams {
    double aperture_diameter_m = 0.025;
    double f_number = 1.0;
    double detector_area_m2 = 1e-7;  // A_pix
    double eta_transmitter = 0.9;
    double eta_receiver = 0.8;
    double quantum_efficiency = 0.7;      // η (avg) at the laser wavelength
    double detector_bandwidth_m = 20e-9;  // Δλ_det (optical filter)
    double integration_time_s = 0;        // τ_int for background/noise; 0 → pulse width
    double noise_irradiance_sigma = 0;    // σ₁ of δE, W/(m²·µm)
    double threshold_gamma = 3.0;         // void if N_laser < γ·ΔN
    double min_range_m = 0.5;
    double max_range_m = 120.0;
    double range_resolution_m = 0.0;  // output quantisation (0 = none)
    int max_returns = 1;  // returns per pulse kept (strongest first when 1), ≤ kMaxReturns
    // Paths beyond the first hit (docs/time-resolved.md §5): surfaces a path may meet (1: the
    // first hit only), and the path weight below which it goes on only by Russian roulette.
    int max_path_depth = 4;
    double path_energy_threshold = 1e-3;
    // Diffuse bounces a path may take (docs/time-resolved.md §5): each bounce point inside the
    // receiver's field of view and in its sight adds light at the whole path's delay; 0: none.
    int diffuse_bounces = 0;
    // Transmitter–receiver overlap O(R) = 1 − exp(−(R/R_o)²) with this R_o (0: full overlap
    // everywhere); weighs the atmosphere's volume backscatter (docs/time-resolved.md §6).
    double overlap_range_m = 0.0;
    // Speckle (docs/time-resolved.md §6): M of the Gamma law of each return's energy; 0: none;
    // kSpeckleAuto: M from the aperture, the beam's divergence and the wavelength.
    double speckle_cells = 0.0;
};
inline constexpr double kSpeckleAuto = -1.0;

// Measurement noise (docs/physics.md eqs. (14)–(15)).
struct NoiseParams {
    double range_sigma_m = 0;     // δR
    double jitter_sigma_rad = 0;  // δxy, per axis
};

// One pulse as fired: time since scan start, direction in the sensor frame (FLU, unit),
// channel (laser id), scan angle for LAS, and the sensor-frame azimuth.
struct PulseSpec {
    std::int64_t t_ns = 0;
    Eigen::Vector3f dir{1, 0, 0};
    std::uint16_t channel = 0;
    float scan_angle_deg = 0;
    float azimuth_deg = 0;
    std::uint8_t scan_direction = 0;       // 1 when the mirror moves in +angle direction
    std::uint8_t edge_of_flight_line = 0;  // 1 on the last pulse of a scan line
    std::uint32_t pixel = 0;               // an array's pixel (ArrayScan), else 0
};

// Where pulses go and when. Pulse k's spec is a pure function of k, so any thread can
// generate any range of pulses. Implementations: spinning multi-beam, oscillating mirror
// (sawtooth/sinusoidal), rotating polygon, Palmer.
class ScanPattern {
  public:
    virtual ~ScanPattern() = default;
    virtual std::string kind() const = 0;
    // Pulses fired in [0, duration).
    virtual std::uint64_t pulse_count(core::Nanos duration) const = 0;
    // Fills out[0..n) with pulses first .. first+n−1.
    virtual void pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const = 0;
    virtual double pulse_rate_hz() const = 0;
    virtual std::uint32_t channels() const = 0;
    // Pulses per firing group (one column of a spinning sensor; 1 for single-beam scanners).
    // The renderer regroups rays of neighbouring groups by channel for coherent tracing.
    virtual std::uint32_t group_size() const { return channels(); }
};

// The vendor packet format a sensor speaks (`mirage emulate`, `mirage live`): a property of the
// model, set by its preset and kept by sensor files based on it, never guessed from the name.
enum class WireFamily : std::uint8_t { None, Velodyne, Ouster };
struct WireIdentity {
    WireFamily family = WireFamily::None;
    std::string model;  // the codec's model name: vlp16, hdl64e-s3, os1-64-1024x10, ...
};

// How the receiver turns light into returns (docs/time-resolved.md §7).
enum class DetectorKind : std::uint8_t {
    Discrete,  // sub-ray hits merged into echoes c·τ/2 apart (physics.md §2.3): the default
    Linear,    // linear-mode APD and waveform digitiser (physics::LinearDetector)
    Geiger,    // Geiger-mode APD: photon events (physics::geiger_events)
};

// The Geiger-mode detector's settings (sensor YAML `detector:` with type geiger;
// docs/photon-counting.md §2). The gate opens at the receiver's minimum range and closes at its
// maximum (arming delay 2·min_range/c); its photon detection efficiency is the receiver's
// quantum efficiency (YAML detector.pde sets it).
struct GeigerDetectorParams {
    double bin_ns = 0.25;             // timing resolution: the gate's bins
    double dark_count_rate_hz = 1e3;  // per pixel, primary
    double dead_time_ns = 50.0;       // after a detection
    bool paralyzable = false;         // a primary event while dead restarts the dead time
    double jitter_ns = 0.0;           // σ of each reported time
    double afterpulse_probability = 0.0;
    double afterpulse_delay_ns = 1000.0;  // mean of the exponential release delay
    // An array pixel's detection fires each of its four neighbours with this probability, at
    // the same time, if armed (docs/photon-counting.md §2).
    double crosstalk_probability = 0.0;
    int max_events = 1;  // per pixel and gate (a framed array reports one)
    // Armed between gates too (an array only): a detection late in one pulse's window keeps the
    // pixel dead into the next one's (docs/photon-counting.md §2.1). Gated (false): every gate
    // opens armed.
    bool free_running = false;
};

// The linear-mode detector's settings (sensor YAML `detector:`; physics::LinearDetector checks
// them and documents each).
// How the linear detector times an echo (docs/time-resolved.md §12).
enum class EchoTiming : std::uint8_t {
    Peak,              // a Gaussian through the maximum (the matched filter for a measured pulse)
    ConstantFraction,  // the leading edge at a fraction of the amplitude, calibrated on the pulse
    Decomposition,     // a least-squares sum of Gaussians over the waveform
};

struct LinearDetectorParams {
    double sample_rate_gsps = 1.0;    // digitiser clock
    int bits = 12;                    // counts 0 … 2^bits − 1
    double offset_counts = 100.0;     // the digitiser's reading without light
    double gain_counts_per_pe = 4.0;  // counts per primary photo-electron in a sample
    double apd_gain = 50.0;           // M: sets the excess noise
    double apd_k = 0.02;              // ionisation ratio k (silicon ~0.02)
    double thermal_noise_pe = 2.0;    // amplifier noise, rms per sample, referred to the input
    double dark_current_na = 0.0;     // primary dark current, referred to the input
    double threshold_counts = 0.0;    // above the baseline; 0: 4σ of the pulse's noise floor
    EchoTiming timing = EchoTiming::Peak;
    double cfd_fraction = 0.5;  // of the echo's amplitude, with EchoTiming::ConstantFraction
};

// A focal-plane array receiver (docs/photon-counting.md §3; sensor YAML `array:`).
enum class Illumination : std::uint8_t {
    Flash,     // the laser lights the whole array's field at once
    Beamlets,  // the laser is split into one beamlet per pixel, each of beam.divergence
};

struct ArrayParams {
    std::uint32_t columns = 0, rows = 0;  // 0: no array, a single-pixel receiver
    double pitch_m = 50e-6;               // pixel pitch on the focal plane
    double focal_length_m = 0.5;          // of the receiver optics: pixel IFOV = pitch / f
    double fill_factor = 1.0;             // photosensitive share of a pixel's area
    Illumination illumination = Illumination::Flash;
    // Set by make_array: the laser's own full divergence and profile (the beam then describes a
    // pixel-pulse), and each pixel's share of the laser's energy.
    double laser_divergence_rad = 0;
    BeamProfile laser_profile = BeamProfile::Gaussian;
    std::vector<float> share;

    bool on() const { return columns > 0; }
    std::uint32_t pixels() const { return columns * rows; }
    double ifov_rad() const { return pitch_m / focal_length_m; }  // per pixel, small angle
};

struct SensorModel {
    std::string name;
    WireIdentity wire;  // None: no packet format (airborne scanners, sensors built from scratch)
    std::shared_ptr<const ScanPattern> scan;
    BeamParams beam;
    ReceiverParams receiver;
    NoiseParams noise;
    DetectorKind detector = DetectorKind::Discrete;
    LinearDetectorParams linear;  // read when detector == Linear
    GeigerDetectorParams geiger;  // read when detector == Geiger
    ArrayParams array;            // on(): an array receiver, scan is an ArrayScan
    std::uint16_t point_source_id = 1;
    bool airborne = false;  // LAS scan angle = off-nadir, previews top-down
};

// Built-in presets: vlp16, vlp16-hires, vlp32c, hdl32e, hdl64e-s3, os<P>-<H>-<W>x<F> (Ouster
// P ∈ {0, 1, 2}, H ∈ {32, 64, 128}, W ∈ {512, 1024, 2048}, F ∈ {10, 20}), and airborne presets
// als-mirror (sawtooth, default), als-mirror-sine, als-polygon, als-palmer.
// The speckle cells M a sensor's returns have (docs/time-resolved.md §6): receiver.speckle_cells,
// or for kSpeckleAuto 1 + A_rx·A_spot/(λR)² = 1 + (π·D·θ_b/(2λ))² (aperture D, the beam's 1/e²
// half-angle θ_b, its spot R·θ_b; R cancels); 0 for none.
double speckle_cells(const SensorModel& m);

std::vector<std::string> preset_names();
SensorModel preset(const std::string& name);            // throws ConfigError if unknown
SensorModel load_sensor_yaml(const std::string& path);  // throws ConfigError with key path
// The same from YAML text in memory; `name` labels errors and gives the default model name.
SensorModel load_sensor_yaml_text(const std::string& yaml, const std::string& name);
// A preset name or a YAML path.
SensorModel resolve_sensor(const std::string& spec);

// Effective configuration, one value per line, plus a per-channel table that repeats the beam and
// receiver values each channel uses (docs/physics.md §3.5: overrides must reach every channel).
// Printed by the CLI at start-up.
std::string describe(const SensorModel& model);

// Footprint sampling of the divergence cone: angular offsets (rad, about two axes orthogonal
// to the beam) and weights (sum 1) from the beam profile. n = 1, 7, 19, 37 … (1 + 6 + 12 + …).
struct SubRay {
    float dx = 0, dy = 0;
    float weight = 1;
};
// `extent`: the outer ring's radius in beam radii (BeamParams::footprint_radius).
std::vector<SubRay> footprint(int n, BeamProfile profile, double divergence_rad,
                              double extent = 1.0);
// True for the hexagonal counts footprint() accepts: 1 + 3·k·(k + 1), k ≥ 0.
bool is_hex_count(int n);
// The rings k of a hexagonal count n = 1 + 3·k·(k + 1), or −1 for any other n.
int ring_count(int n);

}  // namespace mirage::sensor
