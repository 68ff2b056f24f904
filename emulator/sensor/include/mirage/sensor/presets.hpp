// SPDX-License-Identifier: Apache-2.0
#pragma once
#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {

// Receiver tuning shared by the presets and by YAML files without a base.

// Detector area whose IFOV (full angle) is `ifov_rad` behind an aperture of diameter D at f/#:
// focal length F#·D, pixel diameter IFOV·F#·D.
double detector_area_for_ifov(double ifov_rad, double aperture_diameter_m, double f_number);
// Its inverse: the receiver's IFOV (full angle, rad), pixel diameter over focal length.
double ifov_rad(const ReceiverParams& rx);

// σ₁ (W/(m²·µm)) that makes the detector noise floor of docs/physics.md eq. (12) equal `electrons`:
// floor = τ_int·σ₁·λ_mid·Δλ_det[µm]·A_pix·η/(h·c), τ_int = pulse width when unset.
double noise_sigma_for_floor(double electrons, const BeamParams& beam, const ReceiverParams& rx);

// Photo-electrons of a Lambertian target of reflectance ρ at normal incidence, range R, no
// atmosphere: N = E·η_t·η_r·ρ·A_r/(πR²)·λη/(hc) (closed form of radiometry.hpp with
// P_peak·pulse_width = E). Used to pick preset pulse energies.
double lambertian_electrons(const BeamParams& beam, const ReceiverParams& rx, double reflectance,
                            double range_m);

}  // namespace mirage::sensor
