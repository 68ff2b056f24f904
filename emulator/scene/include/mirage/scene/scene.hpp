// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/core/georef.hpp"

namespace mirage::scene {

// Optical properties at the laser wavelength (see physics::monostatic_brdf).
struct Material {
    std::string name;
    double reflectance = 0.5;         // Lambertian diffuse reflectance ρ_d, [0, 1]
    double specular = 0.0;            // weight of a Phong lobe, [0, 1 − ρ_d]
    double specular_exponent = 20.0;  // Phong exponent of that lobe
    bool retroreflective = false;     // corner-cube sheeting: strong return near the source
    double retro_gain = 100.0;  // retroreflective BRDF at the source, sr⁻¹ (Lambertian 0.5 → 0.16)
    // Paths beyond the first hit (docs/time-resolved.md §5): the fraction a thin surface passes
    // on in the same direction (a leaf's transmittance), the fraction it reflects as a perfect
    // mirror, and for glass the refractive index n (0: not glass), which sets both for a pane:
    // transmission (1 − R)², mirror 1 − (1 − R)², with R = ((n − 1)/(n + 1))² per face square to
    // the light (the values kept here); a path takes R at its own incidence (face_reflectance).
    double transmission = 0.0;
    double mirror = 0.0;
    double refractive_index = 0.0;
    std::uint8_t classification = 1;  // LAS class code
    std::uint16_t red = 32768, green = 32768, blue = 32768;

    // Whether a path reaching this surface goes on (transmitted or mirrored).
    bool continues() const { return transmission > 0.0 || mirror > 0.0; }
};

// Fresnel reflectance of one face at normal incidence, ((n − 1)/(n + 1))².
inline double face_reflectance(double n) { return ((n - 1) / (n + 1)) * ((n - 1) / (n + 1)); }

// Fresnel reflectance of one face, air to index n, for unpolarised light arriving at cos θ_i:
// (R_s + R_p)/2 with cos θ_t from Snell's law (docs/time-resolved.md §5). The pane's second face
// meets the light at θ_t from inside and reflects as much. ((n − 1)/(n + 1))² square to it.
inline double face_reflectance(double n, double cos_i) {
    cos_i = std::clamp(cos_i, 0.0, 1.0);
    const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
    const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    const double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// Triangle mesh in float32, coordinates relative to the scene anchor (or to its instance frame).
struct Mesh {
    std::string name;
    std::vector<Eigen::Vector3f> vertices;
    std::vector<Eigen::Vector3i> triangles;  // indices into vertices
    std::vector<std::uint32_t> materials;    // per triangle: index into Scene::materials
};

// One placement of a mesh: world-local = transform * mesh-local (Embree instancing).
struct Instance {
    std::uint32_t mesh = 0;
    Eigen::Affine3d transform{Eigen::Affine3d::Identity()};
};

// Throws ConfigError("<who>triangle i uses vertex v of n") if a triangle indexes outside the
// vertex list. The one index check shared by Scene::add_mesh and the renderers (which read
// vertices unchecked on the hot path).
void check_vertex_indices(const Mesh& mesh, const std::string& who);

struct LoadStats {
    std::uint64_t degenerate_triangles_dropped = 0;  // zero area or repeated vertex
    std::uint64_t triangles = 0;                     // after dropping, counting instances once
};

// The whole static world. Meshes listed in `meshes` and referenced by no Instance are placed
// once with the identity (the common case); meshes referenced by instances are placed only
// through them. Plain data: loaders fill it, renderers read it.
struct Scene {
    std::string description;  // the scene file's own words about itself (may be empty)
    core::Georef georef;
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    LoadStats stats;

    std::uint32_t add_material(Material m);  // returns its index
    std::uint32_t add_mesh(Mesh m);          // returns its index
    // Number of triangles a ray can meet, counting every instance placement.
    std::uint64_t placed_triangle_count() const;
    // Axis-aligned bounds (local frame) of all placed geometry.
    Eigen::AlignedBox3d bounds() const;
};

// One line for start-up summaries: the description, the named meshes, triangle and material
// counts: "a street corner; meshes: ground, kiosk (x3); 3 214 triangles, 4 materials".
std::string describe(const Scene& scene);

}  // namespace mirage::scene
