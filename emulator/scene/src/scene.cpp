// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/scene.hpp"

#include <string>
#include <utility>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::scene {

std::uint32_t Scene::add_material(Material m) {
    materials.push_back(std::move(m));
    return static_cast<std::uint32_t>(materials.size() - 1);
}

void check_vertex_indices(const Mesh& mesh, const std::string& who) {
    const auto nv = static_cast<long long>(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const long long v = mesh.triangles[i][k];
            if (v < 0 || v >= nv) {
                throw ConfigError(who + "triangle " + std::to_string(i) + " uses vertex " +
                                  std::to_string(v) + " of " + std::to_string(nv));
            }
        }
    }
}

std::uint32_t Scene::add_mesh(Mesh m) {
    // Renderers index vertices and materials without checks, so the mesh is validated here once.
    const std::string who = "scene: mesh '" + m.name + "': ";
    if (m.materials.size() != m.triangles.size()) {
        throw ConfigError(who + std::to_string(m.materials.size()) + " materials for " +
                          std::to_string(m.triangles.size()) + " triangles");
    }
    check_vertex_indices(m, who);
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
        if (m.materials[i] >= materials.size()) {
            throw ConfigError(who + "triangle " + std::to_string(i) + " uses material " +
                              std::to_string(m.materials[i]) + " of " +
                              std::to_string(materials.size()));
        }
    }
    stats.triangles += m.triangles.size();
    meshes.push_back(std::move(m));
    return static_cast<std::uint32_t>(meshes.size() - 1);
}

namespace {

std::vector<bool> instanced_meshes(const Scene& s) {
    std::vector<bool> used(s.meshes.size(), false);
    for (const Instance& inst : s.instances) {
        if (inst.mesh < used.size()) used[inst.mesh] = true;
    }
    return used;
}

// Bounds of the vertices that triangles use (unreferenced vertices are not geometry).
Eigen::AlignedBox3d local_bounds(const Mesh& m) {
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3i& t : m.triangles) {
        for (int k = 0; k < 3; ++k) {
            box.extend(m.vertices[static_cast<std::size_t>(t[k])].cast<double>());
        }
    }
    return box;
}

}  // namespace

std::uint64_t Scene::placed_triangle_count() const {
    const std::vector<bool> used = instanced_meshes(*this);
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        if (!used[i]) n += meshes[i].triangles.size();
    }
    for (const Instance& inst : instances) {
        if (inst.mesh < meshes.size()) n += meshes[inst.mesh].triangles.size();
    }
    return n;
}

Eigen::AlignedBox3d Scene::bounds() const {
    const std::vector<bool> used = instanced_meshes(*this);
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        if (!used[i]) {
            const Eigen::AlignedBox3d b = local_bounds(meshes[i]);
            if (!b.isEmpty()) box.extend(b);
        }
    }
    // Small instanced meshes are transformed vertex by vertex (exact); large ones by the corners
    // of their local box, which is conservative and keeps this O(instances).
    constexpr std::size_t kExactVertexLimit = 10000;
    for (const Instance& inst : instances) {
        if (inst.mesh >= meshes.size()) continue;
        const Mesh& m = meshes[inst.mesh];
        if (m.vertices.size() <= kExactVertexLimit) {
            for (const Eigen::Vector3i& t : m.triangles) {
                for (int k = 0; k < 3; ++k) {
                    box.extend(inst.transform *
                               m.vertices[static_cast<std::size_t>(t[k])].cast<double>());
                }
            }
        } else {
            const Eigen::AlignedBox3d b = local_bounds(m);
            if (b.isEmpty()) continue;
            for (int c = 0; c < 8; ++c) {
                box.extend(inst.transform *
                           b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
            }
        }
    }
    return box;
}

std::string describe(const Scene& scene) {
    std::vector<std::uint32_t> placements(scene.meshes.size(), 0);
    for (const Instance& i : scene.instances) ++placements[i.mesh];
    constexpr std::size_t kNamed = 12;  // a summary line, not a listing
    std::string meshes;
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        if (m == kNamed) {
            meshes += " and " + std::to_string(scene.meshes.size() - kNamed) + " more";
            break;
        }
        if (!meshes.empty()) meshes += ", ";
        meshes += scene.meshes[m].name.empty() ? "(unnamed)" : scene.meshes[m].name;
        if (placements[m] > 1) meshes += " (x" + std::to_string(placements[m]) + ")";
    }
    std::string out = scene.description.empty() ? "" : scene.description + "; ";
    return out + "meshes: " + meshes + "; " + std::to_string(scene.placed_triangle_count()) +
           " triangles, " + std::to_string(scene.materials.size()) + " materials";
}

}  // namespace mirage::scene
