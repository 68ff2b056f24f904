// SPDX-License-Identifier: Apache-2.0
// Reference intersector: every ray against every placed triangle, in double precision.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/render/embree_renderer.hpp"

namespace mirage::render {

struct BruteForceRenderer::Impl {
    // One placed triangle in the local frame, pre-transformed (Möller–Trumbore form).
    struct Tri {
        Eigen::Vector3d v0, e1, e2;
        Eigen::Vector3d centre;  // bounding sphere, for a cheap conservative reject
        double radius2;
        std::uint32_t instance, mesh, primitive, material;
    };
    std::vector<Tri> tris;  // ordered by (instance, mesh, primitive) for the tie-break
};

namespace {

std::uint32_t material_of(const scene::Mesh& mesh, std::size_t prim) {
    if (mesh.materials.size() == 1) return mesh.materials[0];
    if (prim < mesh.materials.size()) return mesh.materials[prim];
    return kInvalidId;
}

void check_indices(const scene::Scene& scene, std::size_t m) {
    scene::check_vertex_indices(scene.meshes[m],
                                "brute-force renderer: meshes[" + std::to_string(m) + "]: ");
}

}  // namespace

BruteForceRenderer::BruteForceRenderer(const scene::Scene& scene)
    : impl_(std::make_unique<Impl>()) {
    std::vector<bool> instanced(scene.meshes.size(), false);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (scene.instances[i].mesh >= scene.meshes.size()) {
            throw ConfigError("brute-force renderer: instances[" + std::to_string(i) +
                              "].mesh out of range");
        }
        instanced[scene.instances[i].mesh] = true;
    }
    auto place = [&](std::size_t m, const Eigen::Affine3d& xf, std::uint32_t instance) {
        check_indices(scene, m);
        const scene::Mesh& mesh = scene.meshes[m];
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            auto corner = [&](int k) -> Eigen::Vector3d {
                const auto idx = static_cast<std::size_t>(mesh.triangles[t][k]);
                return xf * mesh.vertices[idx].cast<double>();
            };
            const Eigen::Vector3d a = corner(0), b = corner(1), c = corner(2);
            const Eigen::Vector3d centre = (a + b + c) / 3.0;
            const double r =
                std::max({(a - centre).norm(), (b - centre).norm(), (c - centre).norm()});
            const double r_safe = r * (1.0 + 1e-9) + 1e-12;  // never reject a real hit
            impl_->tris.push_back({a, b - a, c - a, centre, r_safe * r_safe, instance,
                                   static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(t),
                                   material_of(mesh, t)});
        }
    };
    // Placed in ascending (instance, mesh, primitive) order: direct meshes carry
    // instance = kInvalidId, the largest id, so they come after every instance.
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        place(scene.instances[i].mesh, scene.instances[i].transform, static_cast<std::uint32_t>(i));
    }
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        if (!instanced[m]) place(m, Eigen::Affine3d::Identity(), kInvalidId);
    }
}

BruteForceRenderer::~BruteForceRenderer() = default;

void BruteForceRenderer::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    const std::size_t n = std::min(rays.size(), hits.size());  // contract: equal sizes
    for (std::size_t i = 0; i < n; ++i) {
        const Ray& r = rays[i];
        const Eigen::Vector3d o(r.ox, r.oy, r.oz);
        const Eigen::Vector3d d(r.dx, r.dy, r.dz);
        const double tnear = r.tnear;
        double best_t = static_cast<double>(r.tfar);
        const Impl::Tri* best = nullptr;
        const double d2 = d.squaredNorm();
        for (const Impl::Tri& tri : impl_->tris) {
            // The ray's line misses the bounding sphere: no hit (no division on this path).
            const Eigen::Vector3d oc = tri.centre - o;
            if (oc.cross(d).squaredNorm() > tri.radius2 * d2) continue;
            // Möller–Trumbore with inclusive edges (shared edges are never cracks). Signs are
            // folded into det so that the tests need no division.
            const Eigen::Vector3d p = d.cross(tri.e2);
            double det = tri.e1.dot(p);
            if (det == 0.0 || !std::isfinite(det)) continue;
            const double sign = det > 0.0 ? 1.0 : -1.0;
            det *= sign;
            const Eigen::Vector3d s = o - tri.v0;
            const double u = sign * s.dot(p);
            if (u < 0.0 || u > det) continue;
            const Eigen::Vector3d q = s.cross(tri.e1);
            const double v = sign * d.dot(q);
            if (v < 0.0 || u + v > det) continue;
            const double t = sign * tri.e2.dot(q) / det;
            if (t < tnear || t > best_t) continue;
            // Tris are in ascending (instance, mesh, primitive) order, so an exact tie keeps
            // the earlier one.
            if (best && t == best_t) continue;
            best_t = t;
            best = &tri;
        }
        Hit h;
        if (best) {
            h.t = static_cast<float>(best_t);
            h.instance = best->instance;
            h.mesh = best->mesh;
            h.primitive = best->primitive;
            h.material = best->material;
            Eigen::Vector3d nrm = best->e1.cross(best->e2).normalized();
            if (nrm.dot(d) > 0.0) nrm = -nrm;
            h.nx = static_cast<float>(nrm.x());
            h.ny = static_cast<float>(nrm.y());
            h.nz = static_cast<float>(nrm.z());
        }
        hits[i] = h;
    }
}

}  // namespace mirage::render
