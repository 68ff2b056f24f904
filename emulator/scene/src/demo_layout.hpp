// SPDX-License-Identifier: Apache-2.0
// Shared geometry of the demo town (private to mirage_scene): PRNG, terrain, road loop.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mirage/scene/demo_town.hpp"

namespace mirage::scene::demo {

// splitmix64 (Steele, Lea & Flood 2014): tiny, fast, and identical on every platform, unlike
// std:: distributions whose algorithms are implementation-defined.
class SplitMix64 {
  public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  private:
    std::uint64_t state_;
};

// Independent stream per purpose, so changing e.g. the tree count leaves the buildings alone.
inline SplitMix64 stream(std::uint64_t seed, std::uint64_t purpose) {
    SplitMix64 mix(seed ^ (purpose * 0xD1B54A32D192ED03ull));
    return SplitMix64(mix.next());
}

// A matte material with its LAS class and colour (8-bit, stored ×257).
inline Material material(const char* name, double reflectance, std::uint8_t cls, int r, int g,
                         int b) {
    Material m;
    m.name = name;
    m.reflectance = reflectance;
    m.classification = cls;
    m.red = static_cast<std::uint16_t>(r * 257);
    m.green = static_cast<std::uint16_t>(g * 257);
    m.blue = static_cast<std::uint16_t>(b * 257);
    return m;
}

// Box between z0 and z1 with footprint sx × sy centred at (cx, cy), outward winding.
void add_box(Mesh& m, double cx, double cy, double sx, double sy, double z0, double z1,
             std::uint32_t mat);

enum Purpose : std::uint64_t { kHills = 1, kBuildings, kTrees, kCars, kSigns };

// Rolling hills: three plane waves z = Σ a_k sin(κ_k (d_k · p) + φ_k) with random directions
// d_k and phases φ_k. Amplitudes 4 + 3 + 1 m bound |z| by 8 m; the slope is bounded by
// Σ a_k κ_k = 2π(4/600 + 3/350 + 1/200) = 0.127 (7.2°).
struct Hills {
    static constexpr int kWaves = 3;
    double amp[kWaves] = {4.0, 3.0, 1.0};
    double kappa[kWaves];  // 2π / wavelength
    Eigen::Vector2d dir[kWaves];
    double phase[kWaves];

    explicit Hills(std::uint64_t seed);
    double height(double x, double y) const;
    Eigen::Vector2d gradient(double x, double y) const;
    // Upward unit normal of the surface at (x, y).
    Eigen::Vector3d normal(double x, double y) const;
};

// Closed rounded rectangle centred on the origin: half sizes a, b, corner radius r. Arc length
// s = 0 is the middle of the southern straight, heading east; s grows counter-clockwise.
struct RoadLoop {
    double a, b, r;

    double length() const;
    // Point and unit tangent at arc length s (any real s; wraps around the loop).
    void at(double s, Eigen::Vector2d& point, Eigen::Vector2d& tangent) const;
    // Unsigned distance from p to the loop curve.
    double distance(const Eigen::Vector2d& p) const;
    // The same loop moved `offset` metres outward (right of the direction of travel).
    RoadLoop offset(double o) const { return {a + o, b + o, r + o}; }
};

// Road centreline of the town for these options (600 × 400 m, r = 60 m; scaled with size_m
// below 1024 m).
RoadLoop road_loop(const DemoTownOptions& opt);

inline constexpr double kRoadHalfWidth = 4.0;  // 8 m asphalt
inline constexpr double kRoadLift = 0.03;      // asphalt 3 cm above the terrain (no z-fighting)
inline constexpr double kLaneOffset = 2.0;     // driving lane centre, right of the centreline

// A building's lot, drawn from the buildings stream clear of the road and of each other.
struct BuildingLot {
    Eigen::Vector2d centre;
    double w, d, height, yaw,
        radius;      // footprint sides, eave-to-ground height, yaw, bounding circle
    int wall, roof;  // material choices
};
std::vector<BuildingLot> building_lots(const DemoTownOptions& opt, const RoadLoop& loop);

// The camouflaged vehicle (demo_camouflage.cpp): the clear site nearest the town centre, away
// from the road and the buildings, and the vehicle and its net placed there.
struct CamouflageSite {
    Eigen::Vector2d centre;
    double yaw;     // the vehicle's heading
    double radius;  // bounding circle of the net
};
CamouflageSite camouflage_site(const DemoTownOptions& opt, const RoadLoop& loop,
                               const std::vector<BuildingLot>& lots);
void add_camouflaged_vehicle(Scene& s, const CamouflageSite& site, const Hills& hills);

}  // namespace mirage::scene::demo
