// SPDX-License-Identifier: Apache-2.0
// Embree (both APIs) against the double-precision brute-force renderer on random triangle soups.
#include <gtest/gtest.h>

#include <iostream>

#include "render_test_util.hpp"

namespace mirage::render::test {
namespace {

// Triangles of mixed sizes: mostly 0.5–5 m, some 10–50 m, tiny 1 mm and a few 1 km ones.
scene::Mesh random_soup(std::mt19937_64& rng, int count, std::uint32_t material_base,
                        bool per_triangle_materials) {
    std::uniform_real_distribution<double> box(-50.0, 50.0), unit(0.0, 1.0);
    scene::Mesh m;
    m.name = "soup";
    for (int i = 0; i < count; ++i) {
        const double cls = unit(rng);
        double size;
        if (i < 3) {
            size = 1e3;
        } else if (cls < 0.15) {
            size = 1e-3;
        } else if (cls < 0.30) {
            size = 10.0 + 40.0 * unit(rng);
        } else {
            size = 0.5 + 4.5 * unit(rng);
        }
        const Eigen::Vector3d c(box(rng), box(rng), box(rng));
        add_triangle(m, c + size * random_unit(rng), c + size * random_unit(rng),
                     c + size * random_unit(rng));
        if (per_triangle_materials)
            m.materials.push_back(material_base + static_cast<std::uint32_t>(i % 3));
    }
    if (!per_triangle_materials) m.materials.assign(1, material_base);
    return m;
}

struct SoupCase {
    scene::Scene scene;
    std::vector<Ray> rays;
    std::vector<Hit> brute;  // BruteForceRenderer's answers, computed once for all tests
};

SoupCase make_case() {
    SoupCase sc;
    std::mt19937_64 rng(20240611);
    for (int i = 0; i < 4; ++i) push_material(sc.scene, "m" + std::to_string(i));
    push_mesh(sc.scene, random_soup(rng, 1000, 0, true));  // placed directly
    push_mesh(sc.scene, random_soup(rng, 300, 3, false));  // placed by two instances
    scene::Instance a, b;
    a.mesh = b.mesh = 1;
    a.transform = Eigen::Translation3d(30.0, -20.0, 5.0) *
                  Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    b.transform = Eigen::Translation3d(-60.0, 40.0, -10.0) *
                  Eigen::AngleAxisd(-2.1, Eigen::Vector3d(0, 1, 1).normalized()) *
                  Eigen::Scaling(1.5, 0.8, 1.2);
    sc.scene.instances = {a, b};

    // Half the rays aim at a random point of a random placed triangle (so tiny ones get hit),
    // half are fully random; one in ten has a finite tfar.
    const auto tris = placed_triangles(sc.scene);
    std::uniform_real_distribution<double> unit(0.0, 1.0), box(-80.0, 80.0);
    std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
    const int n = 20003;  // not a multiple of 16: exercises the packet tail
    for (int i = 0; i < n; ++i) {
        Eigen::Vector3d o, d;
        if (i % 2 == 0) {
            const PlacedTri& t = tris[pick(rng)];
            double u = unit(rng), v = unit(rng);
            if (u + v > 1) u = 1 - u, v = 1 - v;
            const Eigen::Vector3d target = t.a + u * (t.b - t.a) + v * (t.c - t.a);
            d = random_unit(rng);
            o = target - std::exp(std::log(1.0) + unit(rng) * std::log(200.0)) * d;
        } else {
            o = Eigen::Vector3d(box(rng), box(rng), box(rng));
            d = random_unit(rng);
        }
        Ray r = make_ray(o, d);
        if (i % 10 == 3) r.tfar = static_cast<float>(1.0 + 99.0 * unit(rng));
        sc.rays.push_back(r);
    }
    sc.brute = trace(BruteForceRenderer(sc.scene), sc.rays);
    return sc;
}

const SoupCase& soup_case() {
    static const SoupCase sc = make_case();
    return sc;
}

// The brief's range tolerance, 1e-4·R + 1e-5 m.
double range_tol(double r) { return 1e-4 * r + 1e-5; }

// Float32 error model: Embree works on coordinates of magnitude S (origin, vertices), each
// rounded to ~6e-8·S; a position error δ along the surface turns into δ/|cos i| of range.
// Used for the assertion; the brief's tolerance above is counted and reported as well.
double float_tol(double r, double s, double cos_i) {
    return range_tol(r) + 1e-6 * s / std::max(std::abs(cos_i), 1e-6);
}

// Independent classification: a ray is ambiguous when float32 rounding could legitimately
// change its answer — the ray passes within 1e-6·S of a candidate triangle's boundary (S =
// coordinate magnitude, the float error scale; the distance is measured across the ray, i.e.
// the in-plane margin × |cos incidence|), two hits within the range tolerance, or a hit within
// the tolerance of tfar.
struct Analysis {
    bool near_edge = false, near_tie = false, near_tfar = false;
    bool ambiguous() const { return near_edge || near_tie || near_tfar; }
};

Analysis analyse(const std::vector<PlacedTri>& tris, const Ray& r, double truth_t) {
    Analysis a;
    const Eigen::Vector3d o(r.ox, r.oy, r.oz), d(r.dx, r.dy, r.dz);
    const double tfar = r.tfar;
    const double reach = std::isfinite(truth_t) ? truth_t : tfar;
    int inside_close = 0;
    for (const PlacedTri& tri : tris) {
        const PlaneHit ph = plane_hit(tri, o, d, 1e-3);
        if (!(ph.t >= 0.0)) continue;
        const double tol = range_tol(ph.t);
        if (ph.t > reach + tol) continue;  // beyond the answer (or tfar on a miss)
        const double scale = std::max(o.norm(), (o + ph.t * d).norm()) + tri.frame_scale;
        if (std::abs(ph.margin * ph.cos_i) <= 1e-6 * scale && ph.t <= tfar + tol) {
            a.near_edge = true;
        }
        if (ph.margin >= 0 && std::isfinite(truth_t) && std::abs(ph.t - truth_t) <= tol) {
            ++inside_close;
        }
    }
    a.near_tie = inside_close > 1;
    if (std::isfinite(truth_t) && std::isfinite(tfar)) {
        a.near_tfar = tfar - truth_t <= range_tol(truth_t);
    }
    return a;
}

bool same_ids(const Hit& a, const Hit& b) {
    return a.hit() == b.hit() && a.instance == b.instance && a.mesh == b.mesh &&
           a.primitive == b.primitive;
}

class Soup : public ::testing::TestWithParam<TraceApi> {};

TEST_P(Soup, embree_matches_brute_force_except_float_ambiguous_rays) {
    const SoupCase& sc = soup_case();
    EmbreeOptions opt;
    opt.api = GetParam();
    const EmbreeRenderer embree(sc.scene, opt);
    EXPECT_EQ(embree.build_stats().triangles, 1300u);
    EXPECT_EQ(embree.build_stats().placed_triangles, 1600u);

    const auto he = trace(embree, sc.rays);
    const auto& hb = sc.brute;
    const auto tris = placed_triangles(sc.scene);

    // Ambiguity is analysed for disagreeing rays only (the analysis is O(triangles) per ray).
    std::size_t hits = 0, edge = 0, tie = 0, near_tfar = 0, disagreements = 0;
    std::size_t over_fixed_tol = 0;  // range error above 1e-4·R + 1e-5 m (grazing or R < 1 m)
    std::size_t instanced_hits = 0, tiny_hits = 0;
    ErrorStats range_err;
    for (std::size_t i = 0; i < sc.rays.size(); ++i) {
        const Hit& e = he[i];
        const Hit& b = hb[i];
        if (b.hit()) ++hits;
        if (b.hit() && b.instance != kInvalidId) ++instanced_hits;
        if (e.hit()) {
            EXPECT_TRUE(std::isfinite(e.t) && std::isfinite(e.nx) && std::isfinite(e.ny) &&
                        std::isfinite(e.nz));
            const Eigen::Vector3f n(e.nx, e.ny, e.nz),
                d(sc.rays[i].dx, sc.rays[i].dy, sc.rays[i].dz);
            EXPECT_NEAR(n.norm(), 1.0f, 1e-5f) << "ray " << i;
            EXPECT_LE(n.dot(d), 0.0f) << "ray " << i;
        }
        if (same_ids(e, b)) {
            if (b.hit()) {
                const double err = static_cast<double>(e.t) - static_cast<double>(b.t);
                range_err.add(err);
                const Ray& r = sc.rays[i];
                const Eigen::Vector3d o(r.ox, r.oy, r.oz), d(r.dx, r.dy, r.dz);
                const double cos_i = Eigen::Vector3d(b.nx, b.ny, b.nz).dot(d);
                const double scale =
                    std::max(o.norm(), (o + b.t * d).norm()) +
                    (b.instance != kInvalidId
                         ? sc.scene.instances[b.instance].transform.translation().norm()
                         : 0.0);
                if (std::abs(err) > range_tol(b.t)) ++over_fixed_tol;
                EXPECT_LE(std::abs(err), float_tol(b.t, scale, cos_i))
                    << "ray " << i << " t " << b.t << " cos " << cos_i;
                EXPECT_EQ(e.material, b.material) << "ray " << i;
                const Eigen::Vector3f ne(e.nx, e.ny, e.nz), nb(b.nx, b.ny, b.nz);
                EXPECT_GT(ne.dot(nb), 0.999f) << "ray " << i;
                const PlacedTri* t = nullptr;
                for (const auto& pt : tris) {
                    if (pt.instance == b.instance && pt.mesh == b.mesh &&
                        pt.primitive == b.primitive) {
                        t = &pt;
                        break;
                    }
                }
                if (t && (t->b - t->a).norm() < 0.01) ++tiny_hits;
            }
            continue;
        }
        ++disagreements;
        const Analysis an = analyse(tris, sc.rays[i], b.hit() ? b.t : kInf);
        edge += an.near_edge;
        tie += an.near_tie;
        near_tfar += an.near_tfar;
        EXPECT_TRUE(an.ambiguous())
            << "ray " << i << ": embree " << e.t << " mesh " << e.mesh << " prim " << e.primitive
            << " inst " << e.instance << ", brute force " << b.t << " mesh " << b.mesh << " prim "
            << b.primitive << " inst " << b.instance;
        if (e.hit()) {
            // Even when ambiguous, Embree's answer must be a real (near-)hit of that triangle.
            const Eigen::Vector3d o(sc.rays[i].ox, sc.rays[i].oy, sc.rays[i].oz);
            const Eigen::Vector3d d(sc.rays[i].dx, sc.rays[i].dy, sc.rays[i].dz);
            bool found = false;
            for (const auto& pt : tris) {
                if (pt.instance != e.instance || pt.mesh != e.mesh || pt.primitive != e.primitive)
                    continue;
                const PlaneHit ph = plane_hit(pt, o, d, 1e-3);
                const double scale = std::max(o.norm(), (o + ph.t * d).norm()) + pt.frame_scale;
                const Eigen::Vector3d nrm = (pt.b - pt.a).cross(pt.c - pt.a).normalized();
                found = std::abs(ph.t - e.t) <= float_tol(ph.t, scale, nrm.dot(d)) &&
                        ph.margin * std::abs(ph.cos_i) >= -1e-6 * scale;
            }
            EXPECT_TRUE(found) << "ray " << i << ": Embree hit is not on its triangle";
        }
    }
    const double n = static_cast<double>(sc.rays.size());
    std::cout << "[soup " << (GetParam() == TraceApi::Single ? "rtcIntersect1" : "packets")
              << "] rays " << sc.rays.size() << ", hits " << hits << " (instanced "
              << instanced_hits << ", tiny 1 mm " << tiny_hits << "), disagreements "
              << disagreements << " (near edge " << edge << ", near tie " << tie << ", near tfar "
              << near_tfar << "), range error RMS " << range_err.rms() * 1e3 << " mm max "
              << range_err.max_abs * 1e3 << " mm, above 1e-4*R+1e-5 m: " << over_fixed_tol << "\n";
    RecordProperty("over_fixed_tolerance", static_cast<int>(over_fixed_tol));
    EXPECT_LE(static_cast<double>(over_fixed_tol), 5e-3 * n);
    RecordProperty("disagreements", static_cast<int>(disagreements));
    EXPECT_GT(hits, sc.rays.size() / 2);
    EXPECT_GT(instanced_hits, 500u);
    EXPECT_GT(tiny_hits, 50u);
    EXPECT_LE(static_cast<double>(disagreements), 1e-3 * n);
}

INSTANTIATE_TEST_SUITE_P(Api, Soup, ::testing::Values(TraceApi::Single, TraceApi::Packets),
                         [](const auto& info) {
                             return std::string(info.param == TraceApi::Single ? "single"
                                                                               : "packets");
                         });

TEST(Soup, brute_force_agrees_with_independent_plane_analysis) {
    // Cross-check of the reference itself on rays whose answer is unambiguous.
    const SoupCase& sc = soup_case();
    const auto tris = placed_triangles(sc.scene);
    const std::vector<Ray> rays(sc.rays.begin(), sc.rays.begin() + 4000);
    const auto& hb = sc.brute;
    std::size_t checked = 0, edge = 0, tie = 0, near_tfar = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Eigen::Vector3d o(rays[i].ox, rays[i].oy, rays[i].oz);
        const Eigen::Vector3d d(rays[i].dx, rays[i].dy, rays[i].dz);
        double best = rays[i].tfar;
        const PlacedTri* best_tri = nullptr;
        for (const auto& t : tris) {
            const PlaneHit ph = plane_hit(t, o, d, 0.0);
            if (ph.margin > 1e-9 && ph.t >= 0 && ph.t < best) {
                best = ph.t;
                best_tri = &t;
            }
        }
        const Analysis an = analyse(tris, rays[i], hb[i].hit() ? hb[i].t : kInf);
        edge += an.near_edge;
        tie += an.near_tie;
        near_tfar += an.near_tfar;
        if (an.ambiguous()) continue;
        ++checked;
        ASSERT_EQ(hb[i].hit(), best_tri != nullptr) << "ray " << i;
        if (best_tri) {
            EXPECT_EQ(hb[i].primitive, best_tri->primitive);
            EXPECT_EQ(hb[i].mesh, best_tri->mesh);
            EXPECT_EQ(hb[i].instance, best_tri->instance);
            EXPECT_NEAR(hb[i].t, best, 1e-6 * best + 1e-9);
        }
    }
    const std::size_t ambiguous = rays.size() - checked;
    std::cout << "[soup analysis] ambiguous rays " << ambiguous << " of " << rays.size()
              << " (near edge " << edge << ", near tie " << tie << ", near tfar " << near_tfar
              << ")\n";
    RecordProperty("ambiguous", static_cast<int>(ambiguous));
    // Most ambiguous rays aim at the 1 mm triangles, where 1e-6·S is 10 % of the size.
    EXPECT_LE(static_cast<double>(ambiguous), 0.1 * static_cast<double>(rays.size()));
}

}  // namespace
}  // namespace mirage::render::test
