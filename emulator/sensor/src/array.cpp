// SPDX-License-Identifier: Apache-2.0
// Focal-plane arrays as pixel-pulses (docs/photon-counting.md §3).
#include "mirage/sensor/array.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::sensor {
namespace {

// The most pixels an array may have (a pixel index fits 32 bits with room; 4096 × 4096).
constexpr std::uint64_t kMaxPixels = 4096ull * 4096ull;

// The rotation that takes unit a onto unit b about a × b (Rodrigues without trigonometry:
// c = a·b, w = a × b, R·v = c·v + w × v + w·(w·v)/(1 + c)); opposite vectors turn by π about
// `fallback`, a unit vector orthogonal to a. Made once per laser pulse, applied per pixel.
class Turn {
  public:
    Turn(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& fallback)
        : c_(a.dot(b)), w_(a.cross(b)), fallback_(fallback), opposite_(1.0 + c_ < 1e-12) {}
    Eigen::Vector3d operator()(const Eigen::Vector3d& v) const {
        if (opposite_) return 2.0 * fallback_.dot(v) * fallback_ - v;
        return c_ * v + w_.cross(v) + w_ * (w_.dot(v) / (1.0 + c_));
    }

  private:
    double c_;
    Eigen::Vector3d w_, fallback_;
    bool opposite_;
};

// Pixel i's tangent-plane offset from the array's centre, in pixels.
double centred(std::uint32_t i, std::uint32_t n) { return double(i) - 0.5 * double(n - 1); }

}  // namespace

ArrayScan::ArrayScan(std::shared_ptr<const ScanPattern> laser, const ArrayParams& array,
                     const Eigen::Vector3d& boresight)
    : laser_(std::move(laser)), pixels_(array.pixels()), boresight_(boresight.normalized()) {
    const Eigen::Vector3d u(0.0, -1.0, 0.0);
    const Eigen::Vector3d v = boresight_.cross(u);
    const double ifov = array.ifov_rad();
    pixel_dirs_.reserve(pixels_);
    for (std::uint32_t row = 0; row < array.rows; ++row)
        for (std::uint32_t col = 0; col < array.columns; ++col) {
            const double tx = centred(col, array.columns) * ifov;
            const double ty = centred(row, array.rows) * ifov;
            pixel_dirs_.push_back((boresight_ + tx * u + ty * v).normalized());
        }
}

std::uint64_t ArrayScan::pulse_count(core::Nanos duration) const {
    return laser_->pulse_count(duration) * pixels_;
}

void ArrayScan::pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const {
    const Eigen::Vector3d fallback(0.0, -1.0, 0.0);
    std::size_t done = 0;
    while (done < n) {
        const std::uint64_t k = first + done;
        const std::uint64_t laser = k / pixels_;
        PulseSpec spec;
        laser_->pulses(laser, 1, &spec);
        const Turn turn(boresight_, spec.dir.cast<double>().normalized(), fallback);
        auto p = static_cast<std::uint32_t>(k % pixels_);
        for (; p < pixels_ && done < n; ++p, ++done) {
            PulseSpec& o = out[done];
            o = spec;
            o.dir = turn(pixel_dirs_[p]).cast<float>();
            o.pixel = p;
        }
    }
}

std::vector<float> pixel_shares(const ArrayParams& a) {
    const std::size_t n = a.pixels();
    std::vector<float> share(n, static_cast<float>(1.0 / double(n)));
    if (a.illumination != Illumination::Flash || a.laser_profile != BeamProfile::Gaussian)
        return share;
    // Gaussian exp(−2r²/w²) over the tangent plane: its marginal along one axis integrates to
    // ½·erf(√2·x/w) from the centre.
    const double w = std::tan(0.5 * a.laser_divergence_rad), ifov = a.ifov_rad();
    const auto axis = [&](std::uint32_t i, std::uint32_t count) {
        const double c = centred(i, count) * ifov;
        const double k = std::numbers::sqrt2 / w;
        return 0.5 * (std::erf(k * (c + 0.5 * ifov)) - std::erf(k * (c - 0.5 * ifov)));
    };
    for (std::uint32_t row = 0; row < a.rows; ++row)
        for (std::uint32_t col = 0; col < a.columns; ++col)
            share[std::size_t(row) * a.columns + col] =
                static_cast<float>(axis(col, a.columns) * axis(row, a.rows));
    return share;
}

void make_array(SensorModel& m, const std::string& source) {
    ArrayParams& a = m.array;
    const auto fail = [&](const std::string& key, const std::string& what) {
        throw ConfigError(source + ": array." + key + ": " + what);
    };
    if (a.columns == 0 || a.rows == 0) fail("columns", "an array needs columns and rows ≥ 1");
    if (std::uint64_t(a.columns) * a.rows > kMaxPixels)
        fail("rows", "more than 4096 × 4096 pixels");
    if (!(a.pitch_m > 0) || !(a.focal_length_m > 0)) fail("pitch_um", "pitch and focal length > 0");
    if (!(a.fill_factor > 0 && a.fill_factor <= 1)) fail("fill_factor", "must be in (0, 1]");
    // Pixel lines of sight are tangents from the boresight: keep the array's half field < 60°.
    const double half = 0.5 * a.ifov_rad() * double(std::max(a.columns, a.rows));
    if (!(half < std::tan(std::numbers::pi / 3))) fail("focal_length_mm", "field of view ≥ 120°");
    if (!m.scan) fail("columns", "the sensor has no scan pattern to mount the array on");
    a.laser_divergence_rad = m.beam.divergence_rad;
    a.laser_profile = m.beam.profile;
    if (a.illumination == Illumination::Flash && !(a.laser_divergence_rad > 0) &&
        a.laser_profile == BeamProfile::Gaussian)
        fail("illumination", "a Gaussian flash needs beam.divergence_mrad > 0");
    a.share = pixel_shares(a);
    if (a.illumination == Illumination::Flash) {
        // A pixel-pulse lights the pixel's square of the field: a cone of equal solid angle,
        // π·tan²(β/2) = ifov² (so eq. 2's irradiance is the flash's on that square).
        m.beam.divergence_rad = 2.0 * std::atan(a.ifov_rad() / std::sqrt(std::numbers::pi));
        m.beam.profile = BeamProfile::TopHat;
        m.beam.footprint_radius = 1.0;
    }
    // The pixel sees pitch²·fill / f² (eq. 4′'s Ω_pix): the fill factor cuts signal and
    // background alike.
    m.receiver.f_number = a.focal_length_m / m.receiver.aperture_diameter_m;
    m.receiver.detector_area_m2 = a.pitch_m * a.pitch_m * a.fill_factor;
    const Eigen::Vector3d boresight =
        m.airborne ? Eigen::Vector3d(0, 0, -1) : Eigen::Vector3d(1, 0, 0);
    m.scan = std::make_shared<ArrayScan>(m.scan, a, boresight);
    m.wire = {};  // no vendor packet carries an array
}

void unmake_array(SensorModel& m) {
    if (!m.array.on()) return;
    if (const auto* scan = dynamic_cast<const ArrayScan*>(m.scan.get()))
        m.scan = scan->laser_pattern();
    m.beam.divergence_rad = m.array.laser_divergence_rad;
    m.beam.profile = m.array.laser_profile;
}

}  // namespace mirage::sensor
