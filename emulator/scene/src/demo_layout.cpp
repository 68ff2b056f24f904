// SPDX-License-Identifier: Apache-2.0
#include "demo_layout.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mirage::scene::demo {

namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
}

Hills::Hills(std::uint64_t seed) {
    SplitMix64 rng = stream(seed, kHills);
    const double wavelength[kWaves] = {600.0, 350.0, 200.0};
    for (int k = 0; k < kWaves; ++k) {
        kappa[k] = kTwoPi / wavelength[k];
        const double theta = rng.uniform(0, kTwoPi);
        dir[k] = {std::cos(theta), std::sin(theta)};
        phase[k] = rng.uniform(0, kTwoPi);
    }
}

double Hills::height(double x, double y) const {
    double z = 0;
    for (int k = 0; k < kWaves; ++k) {
        z += amp[k] * std::sin(kappa[k] * (dir[k].x() * x + dir[k].y() * y) + phase[k]);
    }
    return z;
}

Eigen::Vector2d Hills::gradient(double x, double y) const {
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (int k = 0; k < kWaves; ++k) {
        g += amp[k] * kappa[k] * std::cos(kappa[k] * (dir[k].x() * x + dir[k].y() * y) + phase[k]) *
             dir[k];
    }
    return g;
}

Eigen::Vector3d Hills::normal(double x, double y) const {
    const Eigen::Vector2d g = gradient(x, y);
    return Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
}

double RoadLoop::length() const { return 4 * (a - r) + 4 * (b - r) + kTwoPi * r; }

void RoadLoop::at(double s, Eigen::Vector2d& point, Eigen::Vector2d& tangent) const {
    const double total = length();
    s = std::fmod(s, total);
    if (s < 0) s += total;
    // Walk from the south-west end of the southern straight: s = 0 lies a − r further on.
    s += a - r;
    Eigen::Vector2d p(-(a - r), -b);
    double heading = 0;
    const double arc = std::numbers::pi / 2 * r;
    for (int side = 0; side < 8; ++side) {  // two laps' worth of sides covers s + (a − r)
        const Eigen::Vector2d d(std::cos(heading), std::sin(heading));
        const Eigen::Vector2d left(-d.y(), d.x());
        const double straight = 2 * ((side % 2 == 0) ? (a - r) : (b - r));
        if (s <= straight) {
            point = p + s * d;
            tangent = d;
            return;
        }
        s -= straight;
        p += straight * d;
        const Eigen::Vector2d centre = p + r * left;
        if (s <= arc) {
            const double h = heading + s / r;
            point = centre + r * Eigen::Vector2d(std::sin(h), -std::cos(h));
            tangent = {std::cos(h), std::sin(h)};
            return;
        }
        s -= arc;
        heading += std::numbers::pi / 2;
        p = centre + r * Eigen::Vector2d(std::sin(heading), -std::cos(heading));
    }
    point = p;
    tangent = {std::cos(heading), std::sin(heading)};
}

double RoadLoop::distance(const Eigen::Vector2d& p) const {
    // Signed distance of a rounded box, then its magnitude.
    const double qx = std::abs(p.x()) - (a - r);
    const double qy = std::abs(p.y()) - (b - r);
    const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    const double inside = std::min(std::max(qx, qy), 0.0);
    return std::abs(outside + inside - r);
}

RoadLoop road_loop(const DemoTownOptions& opt) {
    const double f = std::min(1.0, opt.size_m / 1024.0);
    return {300.0 * f, 200.0 * f, 60.0 * f};
}

}  // namespace mirage::scene::demo
