// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

struct DemoTownOptions {
    std::uint64_t seed = 1;
    double size_m = 1024.0;       // square side; terrain on a 1 m grid
    double grid_m = 1.0;
    int buildings = 200;
    int trees = 500;
    int cars = 60;
    int signs = 40;
};

// Deterministic town: rolling terrain (2 triangles per grid cell), ~200 buildings with pitched
// roofs, instanced trees, a road loop, retroreflective signs and parked cars; every material
// carries a LAS class. Centred on the local origin; georeferenced in UTM 32N (EPSG 32632).
// Also describes the demo drive and flight (see demo_car_trajectory / demo_flight_trajectory).
Scene make_demo_town(const DemoTownOptions& opt = {});

}  // namespace mirage::scene
