// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/render/renderer.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::render {

enum class BvhQuality { Low, Medium, High };
// rtcIntersect1 per ray, or packets of the machine's native width (rtcIntersect16 or 8)
enum class TraceApi { Single, Packets };

struct EmbreeOptions {
    BvhQuality quality = BvhQuality::Medium;
    TraceApi api = TraceApi::Packets;
    bool robust = false;   // RTC_SCENE_FLAG_ROBUST (watertight)
    bool compact = false;  // RTC_SCENE_FLAG_COMPACT
    // Packet size for TraceApi::Packets: 8 or 16, 0 = the widest the machine traces natively
    // (docs/physics.md §4.3). The hits do not depend on it.
    int packet_width = 0;
    // Extra rtcNewDevice settings. Empty = automatic: "max_isa=avx2" for TraceApi::Single
    // (docs/physics.md §4.3: single rays ran faster with AVX2 kernels than AVX-512), Embree's
    // default otherwise. Build tasking is always Embree's default (all cores).
    std::string device_config;
};

struct EmbreeBuildStats {
    double build_seconds = 0;
    std::uint64_t triangles = 0;         // unique triangles stored (instances counted once)
    std::uint64_t placed_triangles = 0;  // counting every instance placement
    std::uint64_t bvh_bytes = 0;         // Embree memory (RTC_DEVICE memory monitor) after commit
};

// Embree 3 scene: one geometry per mesh; instanced meshes become child scenes placed with
// rtcNewGeometry(RTC_GEOMETRY_TYPE_INSTANCE). All Embree calls of the project live in its .cpp.
// Errors from the device callback are stored and rethrown as mirage::Error after the call;
// invalid meshes (index out of range, material count not 0, 1 or one per triangle, instance of
// an unknown mesh) throw mirage::ConfigError. Triangle index buffers are shared with Embree,
// so the Scene must outlive the renderer (vertices are copied into padded float buffers).
class EmbreeRenderer : public Renderer {
  public:
    explicit EmbreeRenderer(const scene::Scene& scene, EmbreeOptions opt = {});
    ~EmbreeRenderer() override;
    EmbreeRenderer(const EmbreeRenderer&) = delete;
    EmbreeRenderer& operator=(const EmbreeRenderer&) = delete;

    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override;
    void intersect_some(std::span<const Ray> rays, std::span<const std::uint32_t> which,
                        std::span<Hit> hits) const override;
    const EmbreeBuildStats& build_stats() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// O(rays × triangles) reference in double precision with Möller–Trumbore; for tests only.
// Every placed triangle is transformed to the local frame in double at construction; ties in t
// go to the lowest (instance, mesh, primitive). The Scene must outlive the renderer.
class BruteForceRenderer : public Renderer {
  public:
    explicit BruteForceRenderer(const scene::Scene& scene);
    ~BruteForceRenderer() override;
    BruteForceRenderer(const BruteForceRenderer&) = delete;
    BruteForceRenderer& operator=(const BruteForceRenderer&) = delete;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mirage::render
