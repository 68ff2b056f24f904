// SPDX-License-Identifier: Apache-2.0
// Embree ranges against closed-form intersections: plane, (faceted) sphere, box.
#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <map>

#include "render_test_util.hpp"

namespace mirage::render::test {
namespace {

struct Config {
    TraceApi api;
    bool robust;
};

std::string config_name(const ::testing::TestParamInfo<Config>& info) {
    return std::string(info.param.api == TraceApi::Single ? "single" : "packets") +
           (info.param.robust ? "_robust" : "");
}

class ClosedForm : public ::testing::TestWithParam<Config> {
  protected:
    EmbreeOptions options() const {
        EmbreeOptions o;
        o.api = GetParam().api;
        o.robust = GetParam().robust;
        return o;
    }
};

// Plane z = 0 (12 × 12 cells of 100 m) seen from random origins at 1–200 m range and
// incidences up to 89.9°; the truth is the range of the double-precision ray.
TEST_P(ClosedForm, plane_range_error_is_submillimetre_up_to_grazing_incidence) {
    scene::Scene s;
    push_material(s, "ground");
    push_mesh(s, grid_mesh(12, -600, -600, 100, [](double, double) { return 0.0; }));
    const EmbreeRenderer r(s, options());

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0), pos(-300.0, 300.0);
    std::vector<Ray> rays;
    std::vector<double> truth, theta;
    for (int i = 0; i < 20000; ++i) {
        const double range = std::exp(unit(rng) * std::log(200.0));  // 1..200 m
        const double th = (i % 5 == 0 ? 89.0 + 0.9 * unit(rng) : 89.9 * unit(rng)) * kPi / 180;
        const Eigen::Vector3d d =
            incident_direction(Eigen::Vector3d::UnitZ(), th, 2 * kPi * unit(rng));
        const Eigen::Vector3d p(pos(rng), pos(rng), 0.0);
        rays.push_back(make_ray(p - range * d, d));
        truth.push_back(range);
        theta.push_back(th);
    }
    const auto hits = trace(r, rays);
    ErrorStats all, grazing;
    std::size_t missed = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits[i].hit()) {
            ++missed;
            continue;
        }
        const double e = static_cast<double>(hits[i].t) - truth[i];
        all.add(e);
        if (theta[i] > 89.0 * kPi / 180) grazing.add(e);
        EXPECT_EQ(hits[i].mesh, 0u);
        EXPECT_NEAR(std::abs(hits[i].nz), 1.0f, 1e-6f);
    }
    std::cout << "[plane] range error RMS " << all.rms() * 1e3 << " mm, max " << all.max_abs * 1e3
              << " mm; incidence 89–89.9°: RMS " << grazing.rms() * 1e3 << " mm, max "
              << grazing.max_abs * 1e3 << " mm (" << grazing.n << " rays)\n";
    RecordProperty("plane_rms_um", static_cast<int>(all.rms() * 1e6));
    RecordProperty("plane_max_um", static_cast<int>(all.max_abs * 1e6));
    EXPECT_EQ(missed, 0u);
    EXPECT_LE(all.rms(), 0.5e-3);
    EXPECT_LE(all.max_abs, 2e-3);
}

// Icosphere of radius 10 m subdivided 4 times (5120 facets). The facets lie between the sphere
// and the inner sphere of radius R − δ (δ = sagitta), so the faceted range must lie between the
// analytic ranges of those two spheres; it must also equal the double-precision faceted range.
scene::Mesh icosphere(const Eigen::Vector3d& centre, double radius, int levels) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                      {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                      {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    for (auto& x : v) x.normalize();
    std::vector<std::array<int, 3>> f = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(
                (v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
            const int id = static_cast<int>(v.size() - 1);
            mid.emplace(key, id);
            return id;
        };
        std::vector<std::array<int, 3>> g;
        for (const auto& t : f) {
            const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            g.push_back({t[0], a, c});
            g.push_back({t[1], b, a});
            g.push_back({t[2], c, b});
            g.push_back({a, b, c});
        }
        f = std::move(g);
    }
    scene::Mesh m;
    m.name = "icosphere";
    for (const auto& x : v) m.vertices.push_back((centre + radius * x).cast<float>());
    for (const auto& t : f) m.triangles.emplace_back(t[0], t[1], t[2]);
    m.materials.assign(1, 0);
    return m;
}

// Range along a unit ray to a sphere (entry point), +inf if it misses.
double sphere_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& c,
                    double radius) {
    const Eigen::Vector3d oc = o - c;
    const double b = oc.dot(d);
    const double disc = b * b - (oc.squaredNorm() - radius * radius);
    return disc < 0 ? kInf : -b - std::sqrt(disc);
}

TEST_P(ClosedForm, faceted_sphere_range_matches_double_facets_and_lies_within_sagitta_band) {
    const Eigen::Vector3d c(3.0, -2.0, 12.0);
    const double radius = 10.0;
    scene::Scene s;
    push_material(s, "ball");
    push_mesh(s, icosphere(c, radius, 4));
    ASSERT_EQ(s.meshes[0].triangles.size(), 5120u);
    // Sagitta from the float vertices actually stored.
    double inner = radius;
    for (const auto& t : placed_triangles(s)) {
        const Eigen::Vector3d n = (t.b - t.a).cross(t.c - t.a).normalized();
        inner = std::min(inner, std::abs(n.dot(t.a - c)));
    }
    const double sagitta = radius - inner;

    const EmbreeRenderer r(s, options());
    const BruteForceRenderer brute(s);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Ray> rays;
    for (int i = 0; i < 3000; ++i) {
        const Eigen::Vector3d d = random_unit(rng);
        // Impact parameter ≤ 0.9 R: incidence ≤ 64°, no grazing at the sphere.
        Eigen::Vector3d perp = random_unit(rng);
        perp = (perp - perp.dot(d) * d).normalized();
        const double b = 0.9 * radius * std::sqrt(unit(rng));
        const double dist = 15.0 + 135.0 * unit(rng);
        rays.push_back(make_ray(c + b * perp - dist * d, d));
    }
    const auto he = trace(r, rays);
    const auto hb = trace(brute, rays);
    ErrorStats vs_facets;
    std::size_t same_facet = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(he[i].hit() && hb[i].hit()) << "ray " << i;
        const Eigen::Vector3d o(rays[i].ox, rays[i].oy, rays[i].oz);
        const Eigen::Vector3d d(rays[i].dx, rays[i].dy, rays[i].dz);
        const double t_out = sphere_entry(o, d, c, radius);
        const double t_in = sphere_entry(o, d, c, inner);
        const double t = he[i].t;
        const double slack = 1e-6 * o.norm() + 1e-5;
        EXPECT_GE(t, t_out - slack) << "ray " << i;
        EXPECT_LE(t, t_in + slack) << "ray " << i;
        vs_facets.add(t - static_cast<double>(hb[i].t));
        same_facet += he[i].primitive == hb[i].primitive;
    }
    std::cout << "[sphere] sagitta " << sagitta * 1e3 << " mm; Embree vs double facets RMS "
              << vs_facets.rms() * 1e3 << " mm, max " << vs_facets.max_abs * 1e3
              << " mm; same facet " << same_facet << "/" << rays.size() << "\n";
    EXPECT_LE(vs_facets.max_abs, 0.1e-3);
    // Different facets only where the ray crosses a shared edge (within float rounding).
    EXPECT_GE(same_facet, rays.size() - 3);
}

// Box [-1, 2] × [0, 3] × [1, 5] (integer, exactly representable corners). Rays along the box
// edges hit the corners exactly; rays toward points 0.1 mm inside a corner enter the corner
// region; random rays from outside. Truth: the slab method in double.
double slab_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi) {
    double t0 = -kInf, t1 = kInf;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
            continue;
        }
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return (t0 <= t1 && t0 >= 0) ? t0 : kInf;
}

scene::Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    scene::Mesh m;
    m.name = "box";
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back(static_cast<float>(i & 1 ? hi.x() : lo.x()),
                                static_cast<float>(i & 2 ? hi.y() : lo.y()),
                                static_cast<float>(i & 4 ? hi.z() : lo.z()));
    }
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) {
        m.triangles.emplace_back(f[0], f[1], f[2]);
        m.triangles.emplace_back(f[0], f[2], f[3]);
    }
    m.materials.assign(1, 0);
    return m;
}

TEST_P(ClosedForm, box_corner_and_edge_rays_hit_at_the_slab_range) {
    const Eigen::Vector3d lo(-1, 0, 1), hi(2, 3, 5);
    scene::Scene s;
    push_material(s, "box");
    push_mesh(s, box_mesh(lo, hi));
    const EmbreeRenderer r(s, options());

    std::vector<Ray> rays;
    std::vector<std::string> what;
    for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d corner(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                                     i & 4 ? hi.z() : lo.z());
        const Eigen::Vector3d outward((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
        for (int k = 0; k < 3; ++k) {
            // Along the box edge through this corner, from 10 m outside: exact corner hit.
            Eigen::Vector3d dir = Eigen::Vector3d::Zero();
            dir[k] = -outward[k];
            rays.push_back(make_ray(corner - 10.0 * dir, dir));
            what.push_back("edge ray corner " + std::to_string(i) + " axis " + std::to_string(k));
        }
        // Along the main diagonal, exactly through the corner vertex (shared by 6 triangles).
        const Eigen::Vector3d from_diag = corner + 7.0 * outward;
        rays.push_back(make_ray(from_diag, corner - from_diag));
        what.push_back("vertex ray corner " + std::to_string(i));
        // Toward a point 0.1 mm inside the corner, off the diagonal: enters near the corner.
        const Eigen::Vector3d target = corner - 1e-4 * outward;
        const Eigen::Vector3d from = corner + outward.cwiseProduct(Eigen::Vector3d(9.0, 2.0, 4.0));
        rays.push_back(make_ray(from, target - from));
        what.push_back("near-corner ray corner " + std::to_string(i));
    }
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Eigen::Vector3d target =
            lo + Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(hi - lo);
        const Eigen::Vector3d o = 0.5 * (lo + hi) + (5.0 + 50.0 * unit(rng)) * random_unit(rng);
        rays.push_back(make_ray(o, target - o));
        what.push_back("random ray " + std::to_string(i));
    }
    const auto hits = trace(r, rays);
    ErrorStats err;
    std::size_t vertex_leaks = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Eigen::Vector3d o(rays[i].ox, rays[i].oy, rays[i].oz);
        const Eigen::Vector3d d(rays[i].dx, rays[i].dy, rays[i].dz);
        const double truth = slab_entry(o, d, lo, hi);  // parameter along the float ray
        ASSERT_TRUE(std::isfinite(truth)) << what[i];
        const bool ok = hits[i].hit() && std::abs(hits[i].t - truth) <= 1e-5 * truth + 1e-6;
        if (!ok && !GetParam().robust && what[i].starts_with("vertex ray")) {
            // Without RTC_SCENE_FLAG_ROBUST Embree's test is not watertight: a ray through a
            // shared vertex may slip between its triangles. Counted, not failed.
            ++vertex_leaks;
            continue;
        }
        ASSERT_TRUE(hits[i].hit()) << what[i];
        err.add(static_cast<double>(hits[i].t) - truth);
        EXPECT_NEAR(hits[i].t, truth, 1e-5 * truth + 1e-6) << what[i];
    }
    std::cout << "[box] " << rays.size() << " rays, range error RMS " << err.rms() * 1e3
              << " mm, max " << err.max_abs * 1e3
              << " mm; rays through a vertex that leaked: " << vertex_leaks << " of 8\n";
    RecordProperty("vertex_leaks", static_cast<int>(vertex_leaks));
    if (GetParam().robust) {
        EXPECT_EQ(vertex_leaks, 0u);
    }
}

INSTANTIATE_TEST_SUITE_P(Api, ClosedForm,
                         ::testing::Values(Config{TraceApi::Single, false},
                                           Config{TraceApi::Packets, false},
                                           Config{TraceApi::Packets, true}),
                         config_name);

}  // namespace
}  // namespace mirage::render::test
