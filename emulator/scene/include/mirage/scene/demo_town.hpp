// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::scene {

struct DemoTownOptions {
    std::uint64_t seed = 1;
    double size_m = 1024.0;  // square side; terrain on a 1 m grid
    double grid_m = 1.0;
    int buildings = 200;
    int trees = 500;
    int cars = 60;
    int signs = 40;
    bool camouflaged_vehicle = true;
};

// Deterministic town: rolling terrain (2 triangles per grid cell), ~200 buildings with pitched
// roofs, instanced trees, a road loop, retroreflective signs and parked cars; every material
// carries a LAS class. Centred on the local origin; georeferenced in UTM 32N (EPSG 32632).
// Also describes the demo drive and flight (see demo_car_trajectory / demo_flight_trajectory).
//
// Layout (all from opt.seed through a splitmix64 stream, no std:: distributions):
//  - terrain: size_m × size_m centred on the origin, class 2, z = terrain_height(opt, x, y)
//    (sum of three sines, |z| <= 8 m, slope <= 8°);
//  - road: closed rounded rectangle 600 × 400 m (corner radius 60 m; scaled down with size_m
//    below 1024 m), 8 m wide, 3 cm above the terrain, class 11;
//  - buildings: mesh "buildings" (walls class 6, pitched roofs class 6), boxes of 10-20 m
//    footprint whose ground floor starts 0.5 m below the lowest terrain point of the footprint;
//  - trees: mesh "tree" (trunk + crown, class 5) placed by `trees`
//    instances; cars: mesh "car" placed by `cars` instances beside the road, tilted onto the
//    terrain; signs: mesh "sign" (retroreflective plate on a post) placed by `signs`
//    instances facing oncoming traffic;
//  - a camouflaged vehicle: mesh "camouflaged_vehicle" (class 65) under mesh "camouflage_net"
//    (class 66, reflectance 0.4, transmission 0.35: a net with holes) on the clear site nearest
//    the centre (camouflaged_vehicle_pose), which the trees then avoid.
// Throws ConfigError("demo town: ...") on impossible options (size, grid, negative counts).
Scene make_demo_town(const DemoTownOptions& opt = {});

// Ground height (local z, metres) of the demo terrain at local (x, y); the terrain mesh's
// vertices are exactly static_cast<float>(terrain_height(...)) at the grid points.
double terrain_height(const DemoTownOptions& opt, double x, double y);

// A car driving the road loop counter-clockwise in the right-hand lane (2 m outside the
// centreline) at 10 m/s (horizontal speed), starting mid-way along the southern straight heading
// east. Platform origin 1.8 m straight above the road surface; body FLU axes: x along the road
// tangent, z along the terrain normal (the car pitches and rolls with the terrain). Samples
// every 10 ms from `start` to start + duration (laps repeat), Cubic interpolation.
core::Trajectory demo_car_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                     core::Nanos duration);

// Straight, level flight heading east (yaw 0) at 50 m/s, 300 m above the terrain at the town
// centre, along y = 0, passing x = 0 half-way through `duration`. Samples every 100 ms, Cubic.
core::Trajectory demo_flight_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                        core::Nanos duration);

// The camouflaged vehicle's pose: position local x, y and the ground's z there; attitude its
// heading (a yaw). ConfigError when the options place no vehicle.
core::Pose camouflaged_vehicle_pose(const DemoTownOptions& opt);

// A slow pass for a photon-counting array (docs/photon-counting.md §8): level flight heading east
// at 10 m/s, 1 200 m above the camouflaged vehicle's ground, over it half-way through `duration`.
// Samples every 100 ms, Cubic.
core::Trajectory demo_camouflage_trajectory(const DemoTownOptions& opt, core::GpsTime start,
                                            core::Nanos duration);

}  // namespace mirage::scene
