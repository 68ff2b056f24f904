// SPDX-License-Identifier: Apache-2.0
// Focal-plane arrays (docs/photon-counting.md §3): an N × M receiver behind one laser. Each pixel
// of each laser pulse is rendered as a pulse of its own (a pixel-pulse) looking along the pixel's
// line of sight, carrying its share of the laser's energy; the radiometry, detectors and outputs
// then serve an array as they serve a single-pixel sensor.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {

// Pixel-pulse k of an array sensor is laser pulse k / pixels(), pixel k % pixels(); pixel p sits
// at column p % columns, row p / columns.
class ArrayScan final : public ScanPattern {
  public:
    // `boresight`: the laser's direction at the pattern's zero angles (sensor frame): columns run
    // along −y (right, across track), rows along boresight × column axis (down, or aft when the
    // boresight is nadir). Pixel tangents are (column − (C − 1)/2)·ifov and likewise for rows.
    ArrayScan(std::shared_ptr<const ScanPattern> laser, const ArrayParams& array,
              const Eigen::Vector3d& boresight);
    std::string kind() const override { return "array:" + laser_->kind(); }
    std::uint64_t pulse_count(core::Nanos duration) const override;
    void pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const override;
    double pulse_rate_hz() const override { return laser_->pulse_rate_hz() * double(pixels_); }
    std::uint32_t channels() const override { return laser_->channels(); }
    // A whole laser pulse's pixels: chunks and trace batches never split a frame.
    std::uint32_t group_size() const override { return pixels_; }
    const ScanPattern& laser() const { return *laser_; }
    const std::shared_ptr<const ScanPattern>& laser_pattern() const { return laser_; }

  private:
    std::shared_ptr<const ScanPattern> laser_;
    std::uint32_t pixels_;
    Eigen::Vector3d boresight_;
    std::vector<Eigen::Vector3d> pixel_dirs_;  // per pixel, unit, at the boresight
};

// Makes `m` an array sensor (m.array.columns > 0): checks the geometry, keeps the laser's
// divergence and profile in m.array, sets each pixel's energy share, turns the beam into the
// pixel-pulse's (flash: a top-hat cone of the pixel's solid angle; beamlets: unchanged), sets the
// receiver's focal length (f-number) and pixel area (pitch² × fill factor), and wraps the scan in
// an ArrayScan. `source` labels errors (ConfigError). Call once, after beam and receiver are set.
void make_array(SensorModel& m, const std::string& source);

// Undoes make_array's changes to the beam and the scan (the laser's again), keeping the array's
// geometry, so a sensor file based on an array preset sets the laser's keys; nothing for a sensor
// without an array.
void unmake_array(SensorModel& m);

// The laser's share of energy that falls on each pixel (sum ≤ 1): flash with a Gaussian laser of
// 1/e² full divergence θ, the Gaussian integrated over the pixel's square in the tangent plane,
// ¼·[erf(√2·x1/w) − erf(√2·x0/w)]·[erf(√2·y1/w) − erf(√2·y0/w)], w = tan(θ/2); flash with a
// top-hat laser (shaped to the array's field) and beamlets: 1/N each.
std::vector<float> pixel_shares(const ArrayParams& a);

}  // namespace mirage::sensor
