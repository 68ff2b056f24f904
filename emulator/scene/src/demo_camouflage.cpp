// SPDX-License-Identifier: Apache-2.0
// The demo town's camouflaged vehicle: a tracked vehicle under a net with holes, the scene the
// photon-counting demo looks at (docs/photon-counting.md §8).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "demo_layout.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_ops.hpp"
#include "mirage/scene/primitives.hpp"

namespace mirage::scene::demo {
namespace {

constexpr double kNetRadius = 8.0;  // bounding circle of the 13 × 9 m net
constexpr double kYaw = 0.5;        // vehicle heading, rad from east

// A tracked vehicle, x forward, on z = 0 (sunk 0.2 m for slopes): hull 6.6 × 3.4 × 1.5 m,
// turret 3.0 × 2.4 × 0.8 m, a 3.6 m barrel; top of the turret 2.1 m. 36 triangles.
Mesh vehicle_mesh(std::uint32_t paint) {
    Mesh m;
    m.name = "camouflaged_vehicle";
    add_box(m, 0.0, 0.0, 6.6, 3.4, -0.2, 1.3, paint);    // hull
    add_box(m, -0.4, 0.0, 3.0, 2.4, 1.3, 2.1, paint);    // turret
    add_box(m, 2.9, 0.0, 3.6, 0.22, 1.64, 1.86, paint);  // barrel
    return m;
}

// A net pitched over it: a 8 × 5 m top 3 m up, sloping to a 13 × 9 m edge 0.3 m below ground.
// Faces wound outward (away from the vehicle). 10 triangles.
Mesh net_mesh(std::uint32_t net) {
    Mesh m;
    m.name = "camouflage_net";
    const double top[2] = {4.0, 2.5}, edge[2] = {6.5, 4.5};
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; ++k)
        m.vertices.emplace_back(static_cast<float>(sx[k] * top[0]),
                                static_cast<float>(sy[k] * top[1]), 3.0f);
    for (int k = 0; k < 4; ++k)
        m.vertices.emplace_back(static_cast<float>(sx[k] * edge[0]),
                                static_cast<float>(sy[k] * edge[1]), -0.3f);
    m.triangles.emplace_back(0, 1, 2);  // top, normal +z
    m.triangles.emplace_back(0, 2, 3);
    for (int k = 0; k < 4; ++k) {  // side k between top k, k+1 and edge k, k+1: outward
        const int a = k, b = (k + 1) % 4;
        m.triangles.emplace_back(4 + a, 4 + b, b);
        m.triangles.emplace_back(4 + a, b, a);
    }
    m.materials.assign(m.triangles.size(), net);
    return m;
}

}  // namespace

CamouflageSite camouflage_site(const DemoTownOptions& opt, const RoadLoop& loop,
                               const std::vector<BuildingLot>& lots) {
    // Rings of candidates 4 m apart from the centre outward: the first clear one.
    const double reach = opt.size_m / 2 - 2 * kNetRadius;
    for (int ring = 0; 4.0 * ring < reach; ++ring) {
        const double r = 4.0 * ring;
        const int n = std::max(1, static_cast<int>(std::ceil(2 * std::numbers::pi * r / 4.0)));
        for (int k = 0; k < n; ++k) {
            const double a = 2 * std::numbers::pi * k / n;
            const Eigen::Vector2d c(r * std::cos(a), r * std::sin(a));
            if (loop.distance(c) < kRoadHalfWidth + 8.0 + kNetRadius) continue;
            const bool clear = std::all_of(lots.begin(), lots.end(), [&](const BuildingLot& l) {
                return (l.centre - c).norm() >= l.radius + kNetRadius + 4.0;
            });
            if (clear) return {c, kYaw, kNetRadius};
        }
    }
    throw ConfigError("demo town: no clear site for the camouflaged vehicle");
}

void add_camouflaged_vehicle(Scene& s, const CamouflageSite& site, const Hills& hills) {
    // The vehicle in a dark olive paint, class 65. The net: fabric over 65 % of its area with a
    // reflectance of 0.6 (nets match foliage in the near infrared) reflects 0.4 of the light, its
    // holes pass 0.35 on (a leaf's model, time-resolved.md §5); class 66. 65 and 66 are the
    // user-definable LAS classes after the town's vehicles (64).
    Material paint = material("vehicle_paint", 0.15, 65, 75, 80, 50);
    paint.specular = 0.1;
    const std::uint32_t paint_id = s.add_material(paint);
    Material net = material("camouflage_net", 0.4, 66, 90, 110, 60);
    net.transmission = 0.35;
    const std::uint32_t net_id = s.add_material(net);
    Eigen::Affine3d place = Eigen::Affine3d::Identity();
    place.translate(Eigen::Vector3d(site.centre.x(), site.centre.y(),
                                    hills.height(site.centre.x(), site.centre.y())));
    place.rotate(Eigen::AngleAxisd(site.yaw, Eigen::Vector3d::UnitZ()));
    Mesh vehicle = vehicle_mesh(paint_id), cover = net_mesh(net_id);
    transform_mesh(vehicle, place);
    transform_mesh(cover, place);
    s.add_mesh(std::move(vehicle));
    s.add_mesh(std::move(cover));
}

}  // namespace mirage::scene::demo
