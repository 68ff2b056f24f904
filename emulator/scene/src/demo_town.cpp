// SPDX-License-Identifier: Apache-2.0
// The generated demo town (see demo_town.hpp for the layout).
#include "mirage/scene/demo_town.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "demo_layout.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_ops.hpp"
#include "mirage/scene/primitives.hpp"

namespace mirage::scene {

namespace {

using demo::add_box;
using demo::Hills;
using demo::material;
using demo::RoadLoop;
using demo::SplitMix64;

constexpr double kPi = std::numbers::pi;

struct Materials {
    std::uint32_t ground, asphalt, walls[3], roofs[2], bark, crown, paint, glass, tyre, sign_face,
        sign_metal, facade;
};

Materials add_materials(Scene& s) {
    Materials m{};
    m.ground = s.add_material(material("ground", 0.3, 2, 110, 140, 80));
    m.asphalt = s.add_material(material("asphalt", 0.1, 11, 60, 60, 64));
    m.walls[0] = s.add_material(material("wall_plaster", 0.5, 6, 225, 215, 190));
    m.walls[1] = s.add_material(material("wall_brick", 0.3, 6, 160, 80, 60));
    m.walls[2] = s.add_material(material("wall_concrete", 0.35, 6, 170, 170, 165));
    m.roofs[0] = s.add_material(material("roof_tiles", 0.2, 6, 150, 60, 40));
    Material metal_roof = material("roof_metal", 0.25, 6, 90, 100, 110);
    metal_roof.specular = 0.3;
    metal_roof.specular_exponent = 40;
    m.roofs[1] = s.add_material(metal_roof);
    m.bark = s.add_material(material("tree_bark", 0.25, 5, 90, 70, 50));
    // A crown is a shell around foliage: each surface passes 40 % on (time-resolved.md §5), so
    // pulses reach the far side of the crown and the ground below as they do through leaves.
    Material crown = material("tree_crown", 0.4, 5, 60, 120, 50);
    crown.transmission = 0.4;
    m.crown = s.add_material(crown);
    // Vehicles and street furniture: LAS 1.4 class 64 (first user-definable code).
    Material paint = material("car_paint", 0.25, 64, 180, 30, 30);
    paint.specular = 0.4;
    paint.specular_exponent = 60;
    m.paint = s.add_material(paint);
    Material glass = material("car_glass", 0.05, 64, 40, 50, 60);
    glass.specular = 0.5;
    glass.specular_exponent = 200;
    m.glass = s.add_material(glass);
    m.tyre = s.add_material(material("car_tyre", 0.05, 64, 20, 20, 20));
    Material face = material("sign_face", 0.6, 64, 250, 250, 250);
    face.retroreflective = true;
    face.retro_gain = 100;
    m.sign_face = s.add_material(face);
    Material steel = material("sign_metal", 0.3, 64, 150, 150, 155);
    steel.specular = 0.2;
    m.sign_metal = s.add_material(steel);
    // The first building's front: a glass facade (n = 1.5: 92 % through, the rest mirrored).
    Material facade = material("facade_glass", 0.0, 6, 120, 160, 180);
    facade.refractive_index = 1.5;
    facade.transmission = (1 - face_reflectance(1.5)) * (1 - face_reflectance(1.5));
    facade.mirror = 1 - facade.transmission;
    m.facade = s.add_material(facade);
    return m;
}

Eigen::Affine3d place(const Eigen::Vector3d& t, const Eigen::Matrix3d& r, double scale = 1.0) {
    Eigen::Affine3d a = Eigen::Affine3d::Identity();
    a.linear() = r * scale;
    a.translation() = t;
    return a;
}

Eigen::Matrix3d yaw_matrix(double yaw) {
    return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Body axes x = forward projected onto the terrain plane, z = terrain normal (FLU).
Eigen::Matrix3d on_slope(const Eigen::Vector2d& forward, const Eigen::Vector3d& normal) {
    Eigen::Vector3d x(forward.x(), forward.y(), 0.0);
    x = (x - x.dot(normal) * normal).normalized();
    Eigen::Matrix3d m;
    m.col(0) = x;
    m.col(2) = normal;
    m.col(1) = normal.cross(x);
    return m;
}

// Appends a face (fan over the polygon) wound so that its normal points away from `centre`.
void add_face(Mesh& m, std::initializer_list<Eigen::Vector3d> pts, const Eigen::Vector3d& centre,
              std::uint32_t mat) {
    std::vector<Eigen::Vector3d> p(pts);
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& q : p) c += q;
    c /= static_cast<double>(p.size());
    if (n.dot(c - centre) < 0) std::reverse(p.begin(), p.end());
    const int base = static_cast<int>(m.vertices.size());
    for (const auto& q : p) m.vertices.push_back(q.cast<float>());
    for (int i = 1; i + 1 < static_cast<int>(p.size()); ++i) {
        m.triangles.emplace_back(base, base + i, base + i + 1);
        m.materials.push_back(mat);
    }
}

// ---- meshes placed by instances ---------------------------------------------------------------

// Trunk (hexagonal prism, 12 triangles) + crown (ellipsoidal icosphere, 80 triangles): 92.
Mesh tree_mesh(const Materials& mat) {
    Mesh m;
    m.name = "tree";
    constexpr int kSides = 6;
    constexpr double kRadius = 0.18, kBottom = -0.5, kTop = 2.6;  // sunk 0.5 m: no gap on slopes
    for (int i = 0; i < kSides; ++i) {
        const double a = 2 * kPi * i / kSides;
        m.vertices.emplace_back(static_cast<float>(kRadius * std::cos(a)),
                                static_cast<float>(kRadius * std::sin(a)),
                                static_cast<float>(kBottom));
        m.vertices.emplace_back(static_cast<float>(kRadius * std::cos(a)),
                                static_cast<float>(kRadius * std::sin(a)),
                                static_cast<float>(kTop));
    }
    for (int i = 0; i < kSides; ++i) {
        const int b0 = 2 * i, t0 = 2 * i + 1;
        const int b1 = 2 * ((i + 1) % kSides), t1 = b1 + 1;
        // Counter-clockwise seen from outside: bottom-left, bottom-right, top-right, top-left.
        m.triangles.emplace_back(b0, b1, t1);
        m.triangles.emplace_back(b0, t1, t0);
        m.materials.push_back(mat.bark);
        m.materials.push_back(mat.bark);
    }
    Mesh crown = make_icosphere(1.0, 1, mat.crown);
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    t.translate(Eigen::Vector3d(0, 0, 4.6));  // crown 1.8 .. 7.4 m: swallows the trunk top
    t.scale(Eigen::Vector3d(2.2, 2.2, 2.8));
    append_mesh(m, crown, t);
    return m;
}

// Boxy car, x forward, wheels touching z = 0 (4.4 × 1.8 × 1.5 m): 6 boxes, 72 triangles.
Mesh car_mesh(const Materials& mat) {
    Mesh m;
    m.name = "car";
    add_box(m, 0.0, 0.0, 4.4, 1.8, 0.35, 1.05, mat.paint);  // body
    add_box(m, -0.2, 0.0, 2.3, 1.6, 1.05, 1.5, mat.glass);  // cabin
    for (double x : {-1.4, 1.4}) {
        for (double y : {-0.8, 0.8}) add_box(m, x, y, 0.62, 0.26, -0.03, 0.62, mat.tyre);
    }
    return m;
}

// Post + 0.7 m square plate whose retroreflective front faces +x: 24 triangles.
Mesh sign_mesh(const Materials& mat) {
    Mesh m;
    m.name = "sign";
    add_box(m, 0.0, 0.0, 0.08, 0.08, -0.4, 2.6, mat.sign_metal);
    const std::size_t first = m.triangles.size();
    add_box(m, 0.065, 0.0, 0.05, 0.7, 1.9, 2.6, mat.sign_metal);
    // The +x face of the plate box (normal +x) is the retroreflective sheeting.
    for (std::size_t i = first; i < m.triangles.size(); ++i) {
        const Eigen::Vector3i& t = m.triangles[i];
        const Eigen::Vector3f n = (m.vertices[static_cast<std::size_t>(t[1])] -
                                   m.vertices[static_cast<std::size_t>(t[0])])
                                      .cross(m.vertices[static_cast<std::size_t>(t[2])] -
                                             m.vertices[static_cast<std::size_t>(t[0])]);
        if (n.x() > 0.9f * n.norm()) m.materials[i] = mat.sign_face;
    }
    return m;
}

// ---- layout ------------------------------------------------------------------------------------

struct Footprint {
    Eigen::Vector2d centre;
    double radius;  // bounding circle
};

bool clear_of(const std::vector<Footprint>& taken, const Eigen::Vector2d& c, double r, double gap) {
    for (const Footprint& f : taken) {
        const double d = f.radius + r + gap;
        if ((f.centre - c).squaredNorm() < d * d) return false;
    }
    return true;
}

Mesh terrain_mesh(const DemoTownOptions& opt, const Hills& hills, std::uint32_t mat) {
    const auto cells = static_cast<int>(std::lround(opt.size_m / opt.grid_m));
    const int n = cells + 1;
    const double x0 = -opt.size_m / 2;
    Mesh m;
    m.name = "terrain";
    const auto nn = static_cast<std::size_t>(n);
    m.vertices.resize(nn * nn);
    // Row r runs along x at y = y0 + r·grid (south to north).
    for (int r = 0; r < n; ++r) {
        const double y = x0 + r * opt.grid_m;
        for (int c = 0; c < n; ++c) {
            const double x = x0 + c * opt.grid_m;
            m.vertices[static_cast<std::size_t>(r) * nn + static_cast<std::size_t>(c)] =
                Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y),
                                static_cast<float>(hills.height(x, y)));
        }
    }
    m.triangles.resize(2 * static_cast<std::size_t>(cells) * static_cast<std::size_t>(cells));
    std::size_t t = 0;
    for (int r = 0; r < cells; ++r) {
        for (int c = 0; c < cells; ++c) {
            const int sw = r * n + c, se = sw + 1, nw = sw + n, ne = nw + 1;
            m.triangles[t++] = {sw, se, ne};  // counter-clockwise from above (normal up)
            m.triangles[t++] = {sw, ne, nw};
        }
    }
    m.materials.assign(m.triangles.size(), mat);
    return m;
}

Mesh road_mesh(const RoadLoop& loop, const Hills& hills, std::uint32_t mat) {
    const double len = loop.length();
    const auto along = static_cast<int>(std::ceil(len));  // ~1 m steps
    constexpr int kAcross = 8;                            // 1 m steps over 8 m
    Mesh m;
    m.name = "road";
    for (int i = 0; i < along; ++i) {
        Eigen::Vector2d c, t;
        loop.at(len * i / along, c, t);
        const Eigen::Vector2d left(-t.y(), t.x());
        for (int j = 0; j <= kAcross; ++j) {
            const double o = -demo::kRoadHalfWidth + 2 * demo::kRoadHalfWidth * j / kAcross;
            const Eigen::Vector2d p = c + o * left;
            m.vertices.emplace_back(
                static_cast<float>(p.x()), static_cast<float>(p.y()),
                static_cast<float>(hills.height(p.x(), p.y()) + demo::kRoadLift));
        }
    }
    const int row = kAcross + 1;
    for (int i = 0; i < along; ++i) {
        const int a0 = i * row, b0 = ((i + 1) % along) * row;
        for (int j = 0; j < kAcross; ++j) {
            // (i, j) -> (i+1, j) -> (i+1, j+1) -> (i, j+1) turns left: counter-clockwise.
            m.triangles.emplace_back(a0 + j, b0 + j, b0 + j + 1);
            m.triangles.emplace_back(a0 + j, b0 + j + 1, a0 + j + 1);
        }
    }
    m.materials.assign(m.triangles.size(), mat);
    return m;
}

void validate(const DemoTownOptions& opt) {
    auto bad = [](const std::string& what) { throw ConfigError("demo town: " + what); };
    if (!(opt.size_m >= 64 && opt.size_m <= 8192)) bad("size_m must be in [64, 8192]");
    if (!(opt.grid_m > 0) || !std::isfinite(opt.grid_m)) bad("grid_m must be positive");
    const double cells = opt.size_m / opt.grid_m;
    if (std::abs(cells - std::round(cells)) > 1e-6 * cells)
        bad("size_m must be a multiple of grid_m");
    if (cells > 6000) bad("more than 6000 × 6000 terrain cells");
    for (int c : {opt.buildings, opt.trees, opt.cars, opt.signs}) {
        if (c < 0 || c > 100000) bad("object counts must be in [0, 100000]");
    }
}

}  // namespace

namespace demo {

void add_box(Mesh& m, double cx, double cy, double sx, double sy, double z0, double z1,
             std::uint32_t mat) {
    Mesh b = make_box({sx, sy, z1 - z0}, mat);
    append_mesh(m, b, Eigen::Affine3d(Eigen::Translation3d(cx, cy, (z0 + z1) / 2)));
}

std::vector<BuildingLot> building_lots(const DemoTownOptions& opt, const RoadLoop& loop) {
    SplitMix64 rng = stream(opt.seed, kBuildings);
    const double half = opt.size_m / 2;
    std::vector<BuildingLot> lots;
    std::vector<Footprint> taken;
    const long max_tries = 200L * opt.buildings + 1000;
    for (long tries = 0; std::ssize(lots) < opt.buildings && tries < max_tries; ++tries) {
        BuildingLot lot;
        lot.w = rng.uniform(10, 20), lot.d = rng.uniform(10, 20);
        lot.height = rng.uniform(6, 25);
        lot.yaw = rng.uniform(0, kPi);
        // As one constructor call, so the two draws keep the order the town has always had.
        const Eigen::Vector2d c(rng.uniform(-half + 20, half - 20),
                                rng.uniform(-half + 20, half - 20));
        lot.centre = c;
        lot.wall = static_cast<int>(rng.next() % 3);
        lot.roof = static_cast<int>(rng.next() % 2);
        lot.radius = 0.5 * std::hypot(lot.w, lot.d);
        if (loop.distance(lot.centre) < kRoadHalfWidth + 8.0 + lot.radius) continue;
        if (!clear_of(taken, lot.centre, lot.radius, 4.0)) continue;
        taken.push_back({lot.centre, lot.radius});
        lots.push_back(lot);
    }
    return lots;
}

}  // namespace demo

double terrain_height(const DemoTownOptions& opt, double x, double y) {
    return Hills(opt.seed).height(x, y);
}

Scene make_demo_town(const DemoTownOptions& opt) {
    validate(opt);
    const Hills hills(opt.seed);
    const RoadLoop loop = demo::road_loop(opt);
    const double half = opt.size_m / 2;

    Scene s;
    s.georef = core::Georef::projected(32632, {500000.0, 5000000.0, 200.0});
    const Materials mat = add_materials(s);
    s.add_mesh(terrain_mesh(opt, hills, mat.ground));
    s.add_mesh(road_mesh(loop, hills, mat.asphalt));

    // Buildings on their lots (demo_layout.hpp), then the camouflaged vehicle clear of them.
    const std::vector<demo::BuildingLot> lots = demo::building_lots(opt, loop);
    std::vector<Footprint> taken;
    {
        Mesh b;
        b.name = "buildings";
        for (std::size_t i = 0; i < lots.size(); ++i) {
            const demo::BuildingLot& lot = lots[i];
            const Eigen::Vector2d c = lot.centre;
            const double w = lot.w, d = lot.d, height = lot.height, yaw = lot.yaw;
            const int wall = lot.wall, roof = lot.roof;
            taken.push_back({c, lot.radius});
            const int placed = static_cast<int>(i) + 1;

            // Ridge along the longer side: local x' of length lx >= ly.
            const double lx = std::max(w, d), ly = std::min(w, d);
            const Eigen::Matrix2d r = Eigen::Rotation2Dd(yaw).toRotationMatrix();
            Eigen::Vector2d corner[4];
            const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
            double zmin = hills.height(c.x(), c.y()), zmax = zmin;
            for (int k = 0; k < 4; ++k) {
                corner[k] = c + r * Eigen::Vector2d(sx[k] * lx / 2, sy[k] * ly / 2);
                const double z = hills.height(corner[k].x(), corner[k].y());
                zmin = std::min(zmin, z);
                zmax = std::max(zmax, z);
            }
            const double base = zmin - 0.5;  // foundation below the lowest ground point
            const double ridge = zmax + height;
            const double rise = std::min(0.35 * ly, 0.4 * height);
            const double eave = ridge - rise;
            const Eigen::Vector3d centre(c.x(), c.y(), (base + ridge) / 2);
            auto at = [&](const Eigen::Vector2d& p, double z) {
                return Eigen::Vector3d(p.x(), p.y(), z);
            };
            for (int k = 0; k < 4; ++k) {
                const Eigen::Vector2d& p = corner[k];
                const Eigen::Vector2d& q = corner[(k + 1) % 4];
                const bool glass_front = placed == 1 && k == 0;
                add_face(b, {at(p, base), at(q, base), at(q, eave), at(p, eave)}, centre,
                         glass_front ? mat.facade : mat.walls[wall]);
            }
            const Eigen::Vector2d ridge_w = c + r * Eigen::Vector2d(-lx / 2, 0);
            const Eigen::Vector2d ridge_e = c + r * Eigen::Vector2d(lx / 2, 0);
            // Roof planes (south and north of the ridge) and the two gable triangles.
            add_face(
                b,
                {at(corner[0], eave), at(corner[1], eave), at(ridge_e, ridge), at(ridge_w, ridge)},
                centre, mat.roofs[roof]);
            add_face(
                b,
                {at(corner[2], eave), at(corner[3], eave), at(ridge_w, ridge), at(ridge_e, ridge)},
                centre, mat.roofs[roof]);
            add_face(b, {at(corner[1], eave), at(corner[2], eave), at(ridge_e, ridge)}, centre,
                     mat.walls[wall]);
            add_face(b, {at(corner[3], eave), at(corner[0], eave), at(ridge_w, ridge)}, centre,
                     mat.walls[wall]);
        }
        if (!b.triangles.empty()) s.add_mesh(std::move(b));
    }
    if (opt.camouflaged_vehicle) {
        const demo::CamouflageSite site = demo::camouflage_site(opt, loop, lots);
        demo::add_camouflaged_vehicle(s, site, hills);
        taken.push_back({site.centre, site.radius});
    }

    // Trees: one mesh, one instance per tree (random yaw and size, base on the terrain).
    if (opt.trees > 0) {
        SplitMix64 rng = demo::stream(opt.seed, demo::kTrees);
        const std::uint32_t tree = s.add_mesh(tree_mesh(mat));
        const long max_tries = 200L * opt.trees + 1000;
        int placed = 0;
        std::vector<Footprint> trees;
        for (long tries = 0; placed < opt.trees && tries < max_tries; ++tries) {
            const Eigen::Vector2d c(rng.uniform(-half + 5, half - 5),
                                    rng.uniform(-half + 5, half - 5));
            const double scale = rng.uniform(0.7, 1.3);
            const double yaw = rng.uniform(0, 2 * kPi);
            const double radius = 2.2 * scale;
            if (loop.distance(c) < demo::kRoadHalfWidth + 5.0 + radius) continue;
            if (!clear_of(taken, c, radius, 1.0) || !clear_of(trees, c, radius, 0.5)) continue;
            trees.push_back({c, radius});
            ++placed;
            s.instances.push_back(
                {tree, place({c.x(), c.y(), hills.height(c.x(), c.y())}, yaw_matrix(yaw), scale)});
        }
    }

    // Parked cars beside the asphalt, both sides, tilted onto the terrain.
    const double len = loop.length();
    if (opt.cars > 0) {
        SplitMix64 rng = demo::stream(opt.seed, demo::kCars);
        const std::uint32_t car = s.add_mesh(car_mesh(mat));
        std::vector<double> spots[2];
        const long max_tries = 200L * opt.cars + 1000;
        int placed = 0;
        for (long tries = 0; placed < opt.cars && tries < max_tries; ++tries) {
            const double at = rng.uniform(0, len);
            const int side = static_cast<int>(rng.next() & 1);  // 0: right (outer), 1: left
            bool free = true;
            for (double o : spots[side]) {
                const double gap = std::abs(o - at);
                if (std::min(gap, len - gap) < 7.0) free = false;
            }
            if (!free) continue;
            spots[side].push_back(at);
            ++placed;
            Eigen::Vector2d c, t;
            loop.at(at, c, t);
            const Eigen::Vector2d left(-t.y(), t.x());
            const double lateral = side == 0 ? -5.4 : 5.4;
            const Eigen::Vector2d p = c + lateral * left;
            // Cars on the inner side face the other way (right-hand traffic).
            const Eigen::Vector2d fwd = side == 0 ? t : Eigen::Vector2d(-t);
            s.instances.push_back({car, place({p.x(), p.y(), hills.height(p.x(), p.y())},
                                              on_slope(fwd, hills.normal(p.x(), p.y())))});
        }
    }

    // Retroreflective signs 7.5 m from the centreline, faces towards oncoming traffic.
    if (opt.signs > 0) {
        SplitMix64 rng = demo::stream(opt.seed, demo::kSigns);
        const std::uint32_t sign = s.add_mesh(sign_mesh(mat));
        std::vector<double> spots;
        const long max_tries = 200L * opt.signs + 1000;
        int placed = 0;
        for (long tries = 0; placed < opt.signs && tries < max_tries; ++tries) {
            const double at = rng.uniform(0, len);
            const int side = static_cast<int>(rng.next() & 1);
            bool free = true;
            for (double o : spots) {
                const double gap = std::abs(o - at);
                if (std::min(gap, len - gap) < 15.0) free = false;
            }
            if (!free) continue;
            spots.push_back(at);
            ++placed;
            Eigen::Vector2d c, t;
            loop.at(at, c, t);
            const Eigen::Vector2d left(-t.y(), t.x());
            const Eigen::Vector2d p = c + (side == 0 ? -7.5 : 7.5) * left;
            // Right side: traffic comes along +t, so the face (mesh +x) points along −t.
            const double yaw = std::atan2(t.y(), t.x()) + (side == 0 ? kPi : 0.0);
            s.instances.push_back(
                {sign, place({p.x(), p.y(), hills.height(p.x(), p.y())}, yaw_matrix(yaw))});
        }
    }
    return s;
}

}  // namespace mirage::scene
