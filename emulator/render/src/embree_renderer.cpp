// SPDX-License-Identifier: Apache-2.0
// Embree 3 closest-hit renderer. Every Embree call of the project lives in this file.
#include "mirage/render/embree_renderer.hpp"

#include <embree3/rtcore.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "mirage/core/error.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace mirage::render {
namespace {

#if defined(__AVX__)
// A packet's lanes, field by field (RTCRayHit8's or RTCRayHit16's arrays from a lane on).
struct Lanes {
    float *ox, *oy, *oz, *dx, *dy, *dz, *tnear, *tfar;
};

// Rays r[0, 8) into eight lanes: Ray is eight floats in the order of Lanes, so this is an 8 × 8
// transpose in registers (a compiled per-lane loop gathers, which cost a good share of a ray's
// marshalling on AVX2 machines). Without AVX every packet is loaded lane by lane.
inline void transpose8(const Ray* r, const Lanes& out) {
    static_assert(sizeof(Ray) == 8 * sizeof(float) && offsetof(Ray, ox) == 0 &&
                  offsetof(Ray, oy) == 4 && offsetof(Ray, oz) == 8 && offsetof(Ray, dx) == 12 &&
                  offsetof(Ray, dy) == 16 && offsetof(Ray, dz) == 20 &&
                  offsetof(Ray, tnear) == 24 && offsetof(Ray, tfar) == 28);
    const auto* f = reinterpret_cast<const float*>(r);
    __m256 a[8], b[8];
    for (int k = 0; k < 8; ++k) a[k] = _mm256_loadu_ps(f + 8 * k);
    for (int k = 0; k < 8; k += 2) {  // pairs of rays interleaved
        b[k] = _mm256_unpacklo_ps(a[k], a[k + 1]);
        b[k + 1] = _mm256_unpackhi_ps(a[k], a[k + 1]);
    }
    for (int k = 0; k < 8; k += 4) {  // quads of rays: fields (0, 4), (1, 5), (2, 6), (3, 7)
        a[k] = _mm256_shuffle_ps(b[k], b[k + 2], _MM_SHUFFLE(1, 0, 1, 0));
        a[k + 1] = _mm256_shuffle_ps(b[k], b[k + 2], _MM_SHUFFLE(3, 2, 3, 2));
        a[k + 2] = _mm256_shuffle_ps(b[k + 1], b[k + 3], _MM_SHUFFLE(1, 0, 1, 0));
        a[k + 3] = _mm256_shuffle_ps(b[k + 1], b[k + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    float* const field[8] = {out.ox, out.oy, out.oz, out.dx, out.dy, out.dz, out.tnear, out.tfar};
    for (int k = 0; k < 4; ++k) {  // the two halves of the eight rays joined
        _mm256_storeu_ps(field[k], _mm256_permute2f128_ps(a[k], a[k + 4], 0x20));
        _mm256_storeu_ps(field[k + 4], _mm256_permute2f128_ps(a[k], a[k + 4], 0x31));
    }
}
#endif

// Embree reads vertices with 16-byte loads, so a float3 buffer needs 4 bytes after the last
// vertex; Scene::Mesh::vertices gives no such guarantee, hence a padded copy. Triangle
// indices are read as plain uint32 and can be shared as they are.
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
static_assert(sizeof(Eigen::Vector3i) == 3 * sizeof(std::uint32_t));

// Embree recommends flush-to-zero / denormals-are-zero in every tracing thread (docs/physics.md
// §4.1).
void enable_ftz_daz() {
#if defined(__x86_64__) || defined(__i386__)
    thread_local bool done = false;
    if (!done) {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        done = true;
    }
#endif
}

// Ray direction components smaller than this are passed to Embree as +0. Embree 3's safe
// reciprocal (zero_fix in its common/math/vec3fa.h) replaces every component below 1e-18 by
// +1e-18 whatever its sign, while the ray's octant and triangle test keep the sign; a ray whose
// origin lies on a BVH node's bounding plane then culls the node it enters, and in a coherent
// packet every ray of that octant misses with it (flat ground 0.84 m below the sensor, from
// cos(π/2)·sin(θ) ≈ −3e-20 in a scan direction). 1e-12 rad moves a point 2 km away by 2 nm.
constexpr float kTinyDirection = 1e-12f;

inline float snap_tiny(float d) { return std::abs(d) < kTinyDirection ? 0.0f : d; }

std::string mesh_label(const scene::Scene& scene, std::size_t m) {
    std::string label = "meshes[" + std::to_string(m) + "]";
    if (!scene.meshes[m].name.empty()) label += " '" + scene.meshes[m].name + "'";
    return label;
}

void validate_mesh(const scene::Scene& scene, std::size_t m) {
    const scene::Mesh& mesh = scene.meshes[m];
    scene::check_vertex_indices(mesh, "embree renderer: " + mesh_label(scene, m) + ": ");
    const std::size_t nm = mesh.materials.size();
    if (nm > 1 && nm != mesh.triangles.size()) {
        throw ConfigError("embree renderer: " + mesh_label(scene, m) + ": " + std::to_string(nm) +
                          " materials for " + std::to_string(mesh.triangles.size()) +
                          " triangles (expected 0, 1 or one per triangle)");
    }
}

// Owns one geometry reference until the end of scope (the scene keeps its own once attached),
// so an error thrown between creation and attachment does not leak it.
class GeometryRef {
  public:
    explicit GeometryRef(RTCGeometry g) : g_(g) {}
    ~GeometryRef() {
        if (g_) rtcReleaseGeometry(g_);
    }
    GeometryRef(const GeometryRef&) = delete;
    GeometryRef& operator=(const GeometryRef&) = delete;
    RTCGeometry get() const { return g_; }

  private:
    RTCGeometry g_;
};

}  // namespace

struct EmbreeRenderer::Impl {
    const scene::Scene* scene = nullptr;
    EmbreeOptions opt;
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> children;                  // one per instanced mesh
    std::vector<std::vector<float>> vertex_buffers;  // padded copies, alive as long as Embree
    std::vector<Eigen::Matrix3f> instance_normal;    // indexed by Scene::instances index
    // What a hit needs per top-scene geomID, flattened so make_hit chases no scene pointers.
    struct Slot {
        std::uint32_t mesh = kInvalidId, instance = kInvalidId;
        std::uint32_t material = kInvalidId;          // the mesh's only material, else kInvalidId
        const std::uint32_t* per_triangle = nullptr;  // one material per triangle, if so
        std::size_t per_triangle_count = 0;
        const Eigen::Matrix3f* normal_matrix = nullptr;  // instances: inverse transpose
    };
    std::vector<Slot> slots;  // by top-scene geomID
    // Packets of 8 where the machine traces 8 natively and not 16 (AVX2 without AVX-512), where
    // Embree traces a packet of 16 through a slower general path (docs/physics.md §4.3).
    bool packet8 = false;
    EmbreeBuildStats stats;

    std::mutex error_mutex;
    bool error_pending = false;
    std::string error_message;
    std::atomic<std::int64_t> bytes{0};

    ~Impl() {
        if (top) rtcReleaseScene(top);
        for (RTCScene s : children) {
            if (s) rtcReleaseScene(s);
        }
        if (device) rtcReleaseDevice(device);
    }

    static void on_error(void* user, RTCError code, const char* str) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard lock(self->error_mutex);
        if (self->error_pending) return;  // keep the first error: later ones follow from it
        self->error_pending = true;
        self->error_message = std::string(str ? str : "unknown error") + " (code " +
                              std::to_string(static_cast<int>(code)) + ")";
    }

    static bool on_memory(void* user, ssize_t delta, bool /*post*/) {
        static_cast<Impl*>(user)->bytes.fetch_add(static_cast<std::int64_t>(delta),
                                                  std::memory_order_relaxed);
        return true;
    }

    void check(const char* call) {
        std::lock_guard lock(error_mutex);
        if (error_pending) {
            error_pending = false;
            throw Error("embree: " + error_message + " in " + call);
        }
    }

    // Stores the new scene in `slot` first, so that ~Impl releases it if a later check throws.
    RTCScene new_scene(RTCScene& slot) {
        RTCScene s = slot = rtcNewScene(device);
        check("rtcNewScene");
        int flags = RTC_SCENE_FLAG_NONE;
        if (opt.robust) flags |= RTC_SCENE_FLAG_ROBUST;
        if (opt.compact) flags |= RTC_SCENE_FLAG_COMPACT;
        rtcSetSceneFlags(s, static_cast<RTCSceneFlags>(flags));
        check("rtcSetSceneFlags");
        RTCBuildQuality q = RTC_BUILD_QUALITY_MEDIUM;
        if (opt.quality == BvhQuality::Low) q = RTC_BUILD_QUALITY_LOW;
        if (opt.quality == BvhQuality::High) q = RTC_BUILD_QUALITY_HIGH;
        rtcSetSceneBuildQuality(s, q);
        check("rtcSetSceneBuildQuality");
        return s;
    }

    void commit(RTCScene s) {
        const auto t0 = std::chrono::steady_clock::now();
        rtcCommitScene(s);
        const auto t1 = std::chrono::steady_clock::now();
        stats.build_seconds += std::chrono::duration<double>(t1 - t0).count();
        check("rtcCommitScene");
    }

    // Attaches mesh `m` as a triangle geometry of `target`; returns its geomID.
    unsigned attach_mesh(RTCScene target, std::size_t m) {
        const scene::Mesh& mesh = scene->meshes[m];
        const GeometryRef ref(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
        check("rtcNewGeometry(TRIANGLE)");
        RTCGeometry g = ref.get();
        std::vector<float>& vb = vertex_buffers.emplace_back(3 * mesh.vertices.size() + 1, 0.0f);
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
            vb[3 * i + 0] = mesh.vertices[i].x();
            vb[3 * i + 1] = mesh.vertices[i].y();
            vb[3 * i + 2] = mesh.vertices[i].z();
        }
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vb.data(), 0,
                                   3 * sizeof(float), mesh.vertices.size());
        check("rtcSetSharedGeometryBuffer(VERTEX)");
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   mesh.triangles.data(), 0, sizeof(Eigen::Vector3i),
                                   mesh.triangles.size());
        check("rtcSetSharedGeometryBuffer(INDEX)");
        rtcCommitGeometry(g);
        check("rtcCommitGeometry");
        const unsigned id = rtcAttachGeometry(target, g);
        check("rtcAttachGeometry");
        return id;
    }

    // Top-scene geomID `id` is mesh `mesh`, placed directly or as instance `instance`.
    void set_slot(unsigned id, std::uint32_t mesh, std::uint32_t instance) {
        if (slots.size() <= id) slots.resize(id + 1);
        slots[id].mesh = mesh;
        slots[id].instance = instance;
    }

    // Completes every slot with its materials and normal matrix once the scene is built.
    void finish_slots() {
        for (Slot& sl : slots) {
            if (sl.mesh == kInvalidId) continue;
            const auto& mats = scene->meshes[sl.mesh].materials;
            if (mats.size() == 1) {
                sl.material = mats[0];
            } else {
                sl.per_triangle = mats.data();
                sl.per_triangle_count = mats.size();
            }
            if (sl.instance != kInvalidId) sl.normal_matrix = &instance_normal[sl.instance];
        }
    }

    // Converts one Embree hit; `ng` is Embree's unnormalised normal (object space if instanced).
    Hit make_hit(float t, unsigned geom, unsigned inst, unsigned prim, Eigen::Vector3f ng,
                 const Eigen::Vector3f& dir) const {
        Hit h;
        if (geom == RTC_INVALID_GEOMETRY_ID) return h;
        h.t = t;
        h.primitive = prim;
        // Instances are top-level geometries, so instID[0] (or else geomID) names the slot.
        const unsigned id = inst != RTC_INVALID_GEOMETRY_ID ? inst : geom;
        if (id < slots.size()) {
            const Slot& sl = slots[id];
            h.instance = sl.instance;
            h.mesh = sl.mesh;
            h.material = sl.material != kInvalidId      ? sl.material
                         : prim < sl.per_triangle_count ? sl.per_triangle[prim]
                                                        : kInvalidId;
            if (sl.normal_matrix) ng = *sl.normal_matrix * ng;
        }
        const float len2 = ng.squaredNorm();
        Eigen::Vector3f n = (len2 > 0.0f && std::isfinite(len2))
                                ? Eigen::Vector3f(ng * (1.0f / std::sqrt(len2)))
                                : Eigen::Vector3f(-dir);
        if (n.dot(dir) > 0.0f) n = -n;  // face the ray
        h.nx = n.x();
        h.ny = n.y();
        h.nz = n.z();
        return h;
    }

    void trace_single(std::span<const Ray> rays, std::span<Hit> hits) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Ray& r = rays[i];
            RTCRayHit rh;
            rh.ray.org_x = r.ox;
            rh.ray.org_y = r.oy;
            rh.ray.org_z = r.oz;
            rh.ray.tnear = r.tnear;
            rh.ray.dir_x = snap_tiny(r.dx);
            rh.ray.dir_y = snap_tiny(r.dy);
            rh.ray.dir_z = snap_tiny(r.dz);
            rh.ray.time = 0.0f;
            rh.ray.tfar = r.tfar;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.ray.id = static_cast<unsigned>(i);
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(top, &ctx, &rh);
            hits[i] = make_hit(rh.ray.tfar, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID,
                               {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z}, {r.dx, r.dy, r.dz});
        }
    }

    // Packets of W rays (RTCRayHit8 or RTCRayHit16): ray at(k) of k < count, its hit into
    // hits[at(k)].
    template <int W, class RayHitW, bool Contiguous, class At>
    void trace_packets_of(std::span<const Ray> rays, std::size_t count, At at,
                          std::span<Hit> hits) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // callers group neighbouring rays
        alignas(64) RayHitW rh{};  // lanes past the last ray stay defined (and invalid)
        alignas(64) int valid[W];
        // Embree never writes time, mask, id or flags: set them once, not per packet.
        for (std::size_t k = 0; k < W; ++k) {
            rh.ray.time[k] = 0.0f;
            rh.ray.mask[k] = 0xFFFFFFFFu;
            rh.ray.id[k] = static_cast<unsigned>(k);
            rh.ray.flags[k] = 0;
        }
        const Ray* r[W];
        for (std::size_t base = 0; base < count; base += W) {
            const std::size_t n = std::min<std::size_t>(W, count - base);
            for (std::size_t k = 0; k < n; ++k) r[k] = &rays[at(base + k)];
#if defined(__AVX__)
            if (Contiguous && n == W) {  // rays[base, base + W) in a row
                for (std::size_t k = 0; k < W; k += 8)
                    transpose8(r[k], {rh.ray.org_x + k, rh.ray.org_y + k, rh.ray.org_z + k,
                                      rh.ray.dir_x + k, rh.ray.dir_y + k, rh.ray.dir_z + k,
                                      rh.ray.tnear + k, rh.ray.tfar + k});
            } else  // (without AVX, every packet lane by lane)
#endif
            {
                for (std::size_t k = 0; k < n; ++k) {
                    rh.ray.org_x[k] = r[k]->ox, rh.ray.org_y[k] = r[k]->oy;
                    rh.ray.org_z[k] = r[k]->oz, rh.ray.tnear[k] = r[k]->tnear;
                    rh.ray.dir_x[k] = r[k]->dx, rh.ray.dir_y[k] = r[k]->dy;
                    rh.ray.dir_z[k] = r[k]->dz, rh.ray.tfar[k] = r[k]->tfar;
                }
            }
            for (std::size_t k = 0; k < W; ++k) {  // all lanes: a loop that vectorises
                rh.ray.dir_x[k] = snap_tiny(rh.ray.dir_x[k]);
                rh.ray.dir_y[k] = snap_tiny(rh.ray.dir_y[k]);
                rh.ray.dir_z[k] = snap_tiny(rh.ray.dir_z[k]);
                valid[k] = k < n ? -1 : 0;
            }
            // Over all W lanes, a count the compiler knows: vector stores. (Over n lanes it
            // made string stores, whose start-up cost a large share of a ray's marshalling.)
            for (std::size_t k = 0; k < W; ++k) {
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
            }
            if constexpr (W == 16)
                rtcIntersect16(valid, top, &ctx, &rh);
            else
                rtcIntersect8(valid, top, &ctx, &rh);
            for (std::size_t k = 0; k < n; ++k) {
                hits[at(base + k)] =
                    make_hit(rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.instID[0][k],
                             rh.hit.primID[k], {rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]},
                             {r[k]->dx, r[k]->dy, r[k]->dz});
            }
        }
    }

    // Packets of the widest size the machine traces natively (docs/physics.md §4.3).
    // Contiguous: at(k) = k.
    template <bool Contiguous, class At>
    void trace_packets(std::span<const Ray> rays, std::size_t count, At at,
                       std::span<Hit> hits) const {
        if (packet8)
            trace_packets_of<8, RTCRayHit8, Contiguous>(rays, count, at, hits);
        else
            trace_packets_of<16, RTCRayHit16, Contiguous>(rays, count, at, hits);
    }
};

EmbreeRenderer::EmbreeRenderer(const scene::Scene& scene, EmbreeOptions opt)
    : impl_(std::make_unique<Impl>()) {
    Impl& im = *impl_;
    im.scene = &scene;
    im.opt = opt;

    // Validate everything before touching Embree, so bad input reads as ConfigError.
    if (opt.packet_width != 0 && opt.packet_width != 8 && opt.packet_width != 16)
        throw ConfigError("embree renderer: packet width " + std::to_string(opt.packet_width) +
                          " (expected 0, 8 or 16)");
    std::vector<bool> instanced(scene.meshes.size(), false);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const std::uint32_t m = scene.instances[i].mesh;
        if (m >= scene.meshes.size()) {
            throw ConfigError("embree renderer: instances[" + std::to_string(i) +
                              "].mesh = " + std::to_string(m) + " but the scene has " +
                              std::to_string(scene.meshes.size()) + " meshes");
        }
        instanced[m] = true;
    }
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) validate_mesh(scene, m);

    std::string config = opt.device_config;
    if (config.empty() && opt.api == TraceApi::Single) config = "max_isa=avx2";
    im.device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!im.device) {
        throw Error("embree: rtcNewDevice(\"" + config + "\") failed (code " +
                    std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
    }
    rtcSetDeviceErrorFunction(im.device, &Impl::on_error, &im);
    rtcSetDeviceMemoryMonitorFunction(im.device, &Impl::on_memory, &im);
    im.check("rtcNewDevice");
    im.packet8 = opt.packet_width == 8 ||
                 (opt.packet_width == 0 &&
                  rtcGetDeviceProperty(im.device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0 &&
                  rtcGetDeviceProperty(im.device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) == 0);

    im.new_scene(im.top);
    im.children.assign(scene.meshes.size(), nullptr);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const auto ntri = scene.meshes[m].triangles.size();
        if (ntri == 0) continue;
        im.stats.triangles += ntri;
        if (instanced[m]) {
            im.new_scene(im.children[m]);
            im.attach_mesh(im.children[m], m);
            im.commit(im.children[m]);
        } else {
            im.stats.placed_triangles += ntri;
            const unsigned id = im.attach_mesh(im.top, m);
            im.set_slot(id, static_cast<std::uint32_t>(m), kInvalidId);
        }
    }

    im.instance_normal.assign(scene.instances.size(), Eigen::Matrix3f::Identity());
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const scene::Instance& inst = scene.instances[i];
        if (!im.children[inst.mesh]) continue;  // empty mesh
        im.stats.placed_triangles += scene.meshes[inst.mesh].triangles.size();
        const Eigen::Matrix3d lin = inst.transform.linear();
        if (!(std::abs(lin.determinant()) > 0.0)) {
            throw ConfigError("embree renderer: instances[" + std::to_string(i) +
                              "].transform is singular");
        }
        // Normals transform with the inverse transpose (exact for non-uniform scale too).
        im.instance_normal[i] = lin.inverse().transpose().cast<float>();

        const GeometryRef ref(rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_INSTANCE));
        im.check("rtcNewGeometry(INSTANCE)");
        RTCGeometry g = ref.get();
        rtcSetGeometryInstancedScene(g, im.children[inst.mesh]);
        im.check("rtcSetGeometryInstancedScene");
        // Column-major 3x4: the three columns of the linear part, then the translation.
        const Eigen::Matrix<double, 3, 4> m34 = inst.transform.affine();
        float xfm[12];
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 3; ++r) xfm[3 * c + r] = static_cast<float>(m34(r, c));
        }
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
        im.check("rtcSetGeometryTransform");
        rtcCommitGeometry(g);
        im.check("rtcCommitGeometry(INSTANCE)");
        const unsigned id = rtcAttachGeometry(im.top, g);
        im.check("rtcAttachGeometry(INSTANCE)");
        im.set_slot(id, inst.mesh, static_cast<std::uint32_t>(i));
    }

    im.commit(im.top);
    im.finish_slots();
    const std::int64_t total = im.bytes.load();
    im.stats.bvh_bytes = total > 0 ? static_cast<std::uint64_t>(total) : 0;
}

EmbreeRenderer::~EmbreeRenderer() = default;

const EmbreeBuildStats& EmbreeRenderer::build_stats() const { return impl_->stats; }

void EmbreeRenderer::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    enable_ftz_daz();
    const std::size_t n = std::min(rays.size(), hits.size());  // contract: equal sizes
    if (impl_->opt.api == TraceApi::Single) {
        impl_->trace_single(rays.first(n), hits.first(n));
    } else {
        impl_->trace_packets<true>(
            rays, n, [](std::size_t k) { return k; }, hits);
    }
}

void EmbreeRenderer::intersect_some(std::span<const Ray> rays, std::span<const std::uint32_t> which,
                                    std::span<Hit> hits) const {
    if (impl_->opt.api == TraceApi::Single) {
        Renderer::intersect_some(rays, which, hits);
        return;
    }
    enable_ftz_daz();
    impl_->trace_packets<false>(
        rays, which.size(), [&](std::size_t k) { return which[k]; }, hits);
}

}  // namespace mirage::render
