// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>

namespace mirage::render {

// A ray in the scene's local float32 frame (within ~1 km of the anchor).
struct Ray {
    float ox = 0, oy = 0, oz = 0;
    float dx = 0, dy = 0, dz = 1;  // unit direction
    float tnear = 0;
    float tfar = std::numeric_limits<float>::infinity();
};

inline constexpr std::uint32_t kInvalidId = 0xFFFFFFFFu;

struct Hit {
    float t = std::numeric_limits<float>::infinity();  // range along the ray; +inf on miss
    float nx = 0, ny = 0, nz = 0;  // geometric normal in the local frame (unit, facing the ray)
    std::uint32_t material = kInvalidId;
    std::uint32_t mesh = kInvalidId;       // Scene::meshes index
    std::uint32_t primitive = kInvalidId;  // triangle index within the mesh
    std::uint32_t instance = kInvalidId;   // Scene::instances index, kInvalidId if not instanced
    bool hit() const { return t < std::numeric_limits<float>::infinity(); }
};

// Closest-hit intersector. Thread-safe: many threads may call intersect() at once.
class Renderer {
  public:
    virtual ~Renderer() = default;
    // hits.size() must equal rays.size(). Rays are traced in the given order; callers group
    // coherent rays (one beam over neighbouring azimuths) for packet tracing.
    virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits) const = 0;
    // Only rays[which[k]], in that order, each hit into hits[which[k]] (hits.size() ==
    // rays.size()); the others' hits are not touched. By default through intersect(), a few at a
    // time.
    virtual void intersect_some(std::span<const Ray> rays, std::span<const std::uint32_t> which,
                                std::span<Hit> hits) const {
        constexpr std::size_t kStep = 64;
        Ray r[kStep];
        Hit h[kStep];
        for (std::size_t base = 0; base < which.size(); base += kStep) {
            const std::size_t n = std::min(kStep, which.size() - base);
            for (std::size_t k = 0; k < n; ++k) r[k] = rays[which[base + k]];
            intersect(std::span<const Ray>(r, n), std::span<Hit>(h, n));
            for (std::size_t k = 0; k < n; ++k) hits[which[base + k]] = h[k];
        }
    }
};

}  // namespace mirage::render
