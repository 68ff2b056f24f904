// SPDX-License-Identifier: Apache-2.0
// The emitted pulse's temporal shape s(t), unit area, for time-resolved radiometry
// (docs/time-resolved.md §4): the linear-mode detector samples it (physics::WaveformSynth).
// The emitter's property, so it lives with the sensor (the YAML reader checks a measured one).
#pragma once
#include <string>
#include <vector>

namespace mirage::sensor {

class PulseShape {
  public:
    // A Gaussian of full width at half maximum `fwhm_ns` (σ = FWHM / (2·√(2 ln 2))).
    // ConfigError naming `source` unless 0 < fwhm_ns < ∞.
    static PulseShape gaussian(double fwhm_ns, const std::string& source);
    // Relative power at increasing times (ns), linear in between and zero outside. ConfigError
    // naming `source` for fewer than 2 samples, times not finite and strictly increasing, a
    // power negative or not finite, or zero area.
    static PulseShape tabulated(std::vector<double> t_ns, std::vector<double> power,
                                const std::string& source);

    // s(t) in 1/ns, t in ns from the pulse's centroid (its arrival time); ∫ s dt = 1.
    double operator()(double t_ns) const;
    double sigma_ns() const { return sigma_ns_; }  // RMS width about the centroid
    double fwhm_ns() const { return fwhm_ns_; }    // full width at half the peak
    double begin_ns() const { return begin_ns_; }  // support: s = 0 outside [begin, end]
    double end_ns() const { return end_ns_; }

  private:
    PulseShape() = default;
    double sigma_ns_ = 0, fwhm_ns_ = 0, begin_ns_ = 0, end_ns_ = 0;
    std::vector<double> t_, p_;  // tabulated, centroid at 0, unit area; empty for a Gaussian
};

}  // namespace mirage::sensor
