// SPDX-License-Identifier: Apache-2.0
// Optical turbulence along a path (docs/time-resolved.md §6): the refractive-index structure
// constant Cn², constant or the Hufnagel–Valley 5/7 profile, and what it does to a lidar's pulse
// (Andrews & Phillips, weak turbulence, a collimated beam in its far field): the wander of the
// beam's centroid, the short-term spread of its spot, and the wander of the return's image.
#pragma once

namespace mirage::physics {

// Hufnagel–Valley 5/7 (wind 21 m/s, ground value A = 1.7e-14): Cn²(h) in m^(−2/3) at h m above
// the ground (h < 0 as 0).
double hufnagel_valley_57(double h_m);

struct Turbulence {
    double cn2 = 0.0;              // m^(−2/3), the same along every path
    bool hufnagel_valley = false;  // instead, HV 5/7 by height above the scene's z = 0
    bool on() const { return cn2 > 0.0 || hufnagel_valley; }
    double cn2_at(double h_m) const { return hufnagel_valley ? hufnagel_valley_57(h_m) : cn2; }
    // ⟨r_c²⟩ (m², both axes together) of a collimated beam of radius w0 after a straight path of
    // `length` from height h0 to h1: 7.26·L³·w0^(−1/3)·∫₀¹ Cn²(h(ξ))·(1 − ξ)² dξ, ξ from the
    // transmitter; 2.42·Cn²·L³·w0^(−1/3) for a constant Cn².
    double beam_wander_m2(double length_m, double w0_m, double h0_m, double h1_m) const;
    // W_ST² − W² (m², the spot's 1/e² radius squared) the turbulence adds to the short-term spot:
    // the long-term spread W²·1.33·σ_R²·Λ^(5/6) less the wander, in the far field
    // L³·w0^(−1/3)·∫₀¹ Cn²(h(ξ))·(9.793·(1 − ξ)^(5/3) − 7.26·(1 − ξ)²) dξ; 1.252·Cn²·L³·w0^(−1/3)
    // for a constant Cn².
    double beam_spread_m2(double length_m, double w0_m, double h0_m, double h1_m) const;
    // ⟨β²⟩ (rad², per axis) of the angle of arrival of the light a point at `length` returns
    // to an aperture of diameter d at height h0 (a spherical wave from h1):
    // 2.91·L·d^(−1/3)·∫₀¹ Cn²(h(ξ))·(1 − ξ)^(5/3) dξ, ξ from the receiver; 1.09·Cn²·L·d^(−1/3)
    // for a constant Cn².
    double image_wander_rad2(double length_m, double d_m, double h0_m, double h1_m) const;
};

}  // namespace mirage::physics
