// SPDX-License-Identifier: Apache-2.0
// Extremes: 0.1 m – 2 km ranges, 89.9° incidence, a 10 km ground and 1 mm triangles, tnear and
// tfar clipping — under every build option.
#include <gtest/gtest.h>

#include <iostream>

#include "render_test_util.hpp"

namespace mirage::render::test {
namespace {

class Stress : public ::testing::TestWithParam<EmbreeOptions> {};

std::string options_name(const ::testing::TestParamInfo<EmbreeOptions>& info) {
    const EmbreeOptions& o = info.param;
    std::string n = o.api == TraceApi::Single ? "single" : "packets";
    n += o.quality == BvhQuality::Low    ? "_low"
         : o.quality == BvhQuality::High ? "_high"
                                         : "_medium";
    if (o.robust) n += "_robust";
    if (o.compact) n += "_compact";
    return n;
}

struct Tiny {
    Eigen::Vector3d centroid, normal;
};

TEST_P(Stress, extreme_ranges_and_sizes_give_finite_hits_where_expected) {
    scene::Scene s;
    push_material(s, "ground");
    push_material(s, "chip");
    // 10 km × 10 km ground at z = 0 in two triangles.
    scene::Mesh ground;
    ground.name = "ground";
    add_triangle(ground, {-5000, -5000, 0}, {5000, -5000, 0}, {5000, 5000, 0});
    add_triangle(ground, {-5000, -5000, 0}, {5000, 5000, 0}, {-5000, 5000, 0});
    ground.materials.assign(1, 0);
    push_mesh(s, ground);
    // 300 equilateral 1 mm triangles, 1–5 m above the ground within ±50 m, facing up-ish.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0), pos(-50.0, 50.0);
    scene::Mesh chips;
    chips.name = "chips";
    std::vector<Tiny> tiny;
    while (tiny.size() < 300) {
        const Eigen::Vector3d n = random_unit(rng);
        if (n.z() < 0.5) continue;
        const Eigen::Vector3d c(pos(rng), pos(rng), 1.0 + 4.0 * unit(rng));
        const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
        const double rad = 1e-3 / std::sqrt(3.0);  // circumradius of a 1 mm-sided triangle
        auto corner = [&](double ang) { return c + rad * (std::cos(ang) * a + std::sin(ang) * b); };
        add_triangle(chips, corner(0), corner(2 * kPi / 3), corner(4 * kPi / 3));
        tiny.push_back({c, n});
    }
    chips.materials.assign(1, 1);
    push_mesh(s, chips);
    const EmbreeRenderer r(s, GetParam());

    std::vector<Ray> rays;
    std::vector<double> expect_t;
    std::vector<std::uint32_t> expect_mesh, expect_prim;
    auto expect = [&](const Ray& ray, double t, std::uint32_t mesh, std::uint32_t prim) {
        rays.push_back(ray);
        expect_t.push_back(t);
        expect_mesh.push_back(mesh);
        expect_prim.push_back(prim);
    };
    // Ground: ranges 0.1 m – 2 km, incidences up to 89.9°, hit points within ±2 km, origins
    // high enough not to pass the chips (above 6 m or away from the ±51 m chip square).
    for (int i = 0; i < 6000; ++i) {
        const double range = 0.1 * std::exp(unit(rng) * std::log(2e4));
        const double th = (i % 4 == 0 ? 89.0 + 0.9 * unit(rng) : 89.9 * unit(rng)) * kPi / 180;
        const Eigen::Vector3d d =
            incident_direction(Eigen::Vector3d::UnitZ(), th, 2 * kPi * unit(rng));
        const Eigen::Vector3d p(200 + 1800 * unit(rng), -2000 + 4000 * unit(rng), 0.0);
        expect(make_ray(p - range * d, d), range, 0, kInvalidId);
    }
    // Chips: aimed at the centroid from 0.1–100 m, from above, incidence ≤ 80°.
    for (std::size_t k = 0; k < tiny.size(); ++k) {
        for (int j = 0; j < 10; ++j) {
            Eigen::Vector3d d;
            do {
                d = incident_direction(tiny[k].normal, 80.0 * unit(rng) * kPi / 180,
                                       2 * kPi * unit(rng));
            } while (d.z() > -0.2);
            const double range = 0.1 * std::exp(unit(rng) * std::log(1e3));
            // Another chip could sit in the way; the ground cannot (the origin is above it).
            expect(make_ray(tiny[k].centroid - range * d, d), range, 1,
                   static_cast<std::uint32_t>(k));
        }
    }
    // Upward rays miss; tfar short of the ground misses; tnear past a chip reaches the ground.
    for (int i = 0; i < 500; ++i) {
        const Eigen::Vector3d o(pos(rng), pos(rng), 0.5 + 10 * unit(rng));
        Eigen::Vector3d d = random_unit(rng);
        d.z() = 0.1 + std::abs(d.z());
        expect(make_ray(o, d), kInf, kInvalidId, kInvalidId);
        const Eigen::Vector3d down(0.01, -0.02, -1.0);
        Ray clipped = make_ray(Eigen::Vector3d(600 + o.x(), o.y(), o.z()), down);
        const double to_ground = o.z() / down.normalized().cwiseAbs().z();
        clipped.tfar = static_cast<float>(0.999 * to_ground);
        expect(clipped, kInf, kInvalidId, kInvalidId);
    }
    for (std::size_t k = 0; k < 50; ++k) {
        const Eigen::Vector3d o = tiny[k].centroid + Eigen::Vector3d(0, 0, 0.5);
        Ray past = make_ray(o, -Eigen::Vector3d::UnitZ());
        past.tnear = 0.6f;
        expect(past, o.z(), 0, kInvalidId);
    }

    const auto hits = trace(r, rays);
    ErrorStats ground_err, chip_err;
    std::size_t chip_hits = 0, chip_blocked = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit& h = hits[i];
        if (!std::isfinite(expect_t[i])) {
            EXPECT_FALSE(h.hit()) << "ray " << i;
            EXPECT_EQ(h.t, std::numeric_limits<float>::infinity());
            EXPECT_EQ(h.mesh, kInvalidId);
            EXPECT_EQ(h.primitive, kInvalidId);
            EXPECT_EQ(h.instance, kInvalidId);
            EXPECT_EQ(h.material, kInvalidId);
            continue;
        }
        ASSERT_TRUE(h.hit()) << "ray " << i << " expected t " << expect_t[i];
        ASSERT_TRUE(std::isfinite(h.t) && std::isfinite(h.nx) && std::isfinite(h.ny) &&
                    std::isfinite(h.nz))
            << "ray " << i;
        const Eigen::Vector3f n(h.nx, h.ny, h.nz), d(rays[i].dx, rays[i].dy, rays[i].dz);
        EXPECT_NEAR(n.norm(), 1.0f, 1e-5f) << "ray " << i;
        EXPECT_LT(n.dot(d), 0.0f) << "ray " << i;
        EXPECT_GE(h.t, rays[i].tnear);
        if (expect_mesh[i] == 1 && h.mesh == 1 && h.primitive != expect_prim[i] &&
            h.t < expect_t[i]) {
            ++chip_blocked;  // another chip in front: legitimate
            continue;
        }
        EXPECT_EQ(h.mesh, expect_mesh[i]) << "ray " << i;
        if (expect_mesh[i] == 1) {
            EXPECT_EQ(h.primitive, expect_prim[i]) << "ray " << i;
            EXPECT_EQ(h.material, 1u);
            chip_err.add(h.t - expect_t[i]);
            ++chip_hits;
        } else {
            EXPECT_EQ(h.material, 0u);
            ground_err.add(h.t - expect_t[i]);
        }
        EXPECT_LE(std::abs(h.t - expect_t[i]), 1e-4 * expect_t[i] + 1e-5) << "ray " << i;
    }
    std::cout << "[stress " << options_name({GetParam(), 0}) << "] ground range error RMS "
              << ground_err.rms() * 1e3 << " mm, max " << ground_err.max_abs * 1e3
              << " mm; 1 mm chips hit " << chip_hits << " (blocked by another chip " << chip_blocked
              << "), range error max " << chip_err.max_abs * 1e3 << " mm\n";
    EXPECT_GE(chip_hits, 2900u);
}

// Direction components smaller than 1e-18 (trigonometric noise such as cos(π/2)·sin(θ), ~1e-20):
// Embree 3's safe reciprocal (zero_fix in common/math/vec3fa.h) turns every such component into
// +1e-18, whatever its sign, while the ray's octant and the triangle test keep the sign. A ray
// whose origin lies on a BVH node's bounding plane then culls the node it enters (it missed flat
// ground 0.84 m below it), and in a coherent packet every ray of that octant missed with it. The
// origin sits exactly above a grid vertex, so the planes x = 0 and y = 0 bound nodes.
TEST_P(Stress, tiny_direction_components_hit_ground_below_an_origin_on_a_node_plane) {
    scene::Scene s;
    push_material(s, "ground");
    push_mesh(s, grid_mesh(400, -200.0, -200.0, 1.0, [](double, double) { return 1.0; }));
    const EmbreeRenderer r(s, GetParam());
    const double h = 0.8;  // the origin above the ground
    std::vector<Ray> rays;
    const float tiny[] = {-0x1.21295ap-65f, 0x1.21295ap-65f, -1e-30f, -0.0f, 0.0f,
                          -2.2e-4f,         2.2e-4f,         -1e-19f};
    for (float a : tiny) {
        for (float b : tiny) {
            for (const Eigen::Vector3d& d :
                 {Eigen::Vector3d(a, 0.34, -0.94), Eigen::Vector3d(0.34, a, -0.94),
                  Eigen::Vector3d(a, b, -1.0), Eigen::Vector3d(-0.5, b, -0.8)}) {
                Ray ray;
                ray.ox = 0.0f;
                ray.oy = 0.0f;
                ray.oz = static_cast<float>(1.0 + h);
                const Eigen::Vector3f u = d.normalized().cast<float>();
                ray.dx = d.x() == a ? a : u.x();  // keep the tiny component as it is
                ray.dy = d.y() == b ? b : u.y();
                ray.dz = u.z();
                ray.tfar = 100.0f;
                rays.push_back(ray);
            }
        }
    }
    const auto hits = trace(r, rays);
    std::size_t missed = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const double expect =
            h / -double(rays[i].dz) * Eigen::Vector3d(rays[i].dx, rays[i].dy, rays[i].dz).norm();
        if (hits[i].hit() && std::abs(hits[i].t - expect) < 1e-5) continue;
        if (++missed <= 4)
            ADD_FAILURE() << "ray " << i << " dir (" << rays[i].dx << ", " << rays[i].dy << ", "
                          << rays[i].dz << "): t " << hits[i].t << ", expected " << expect;
    }
    EXPECT_EQ(missed, 0u) << "of " << rays.size() << " rays";
}

EmbreeOptions opts(TraceApi api, BvhQuality q, bool robust, bool compact) {
    EmbreeOptions o;
    o.api = api;
    o.quality = q;
    o.robust = robust;
    o.compact = compact;
    return o;
}

INSTANTIATE_TEST_SUITE_P(Options, Stress,
                         ::testing::Values(opts(TraceApi::Single, BvhQuality::Medium, false, false),
                                           opts(TraceApi::Packets, BvhQuality::Medium, false,
                                                false),
                                           opts(TraceApi::Packets, BvhQuality::Low, true, false),
                                           opts(TraceApi::Single, BvhQuality::High, false, true)),
                         options_name);

}  // namespace
}  // namespace mirage::render::test
