// SPDX-License-Identifier: Apache-2.0
// Small scenes, scan patterns and sinks for pipeline tests.
#pragma once
#include <functional>
#include <numbers>
#include <vector>

#include "mirage/physics/radiometry.hpp"
#include "mirage/physics/waveform.hpp"
#include "mirage/render/embree_renderer.hpp"
#include "mirage/render/pipeline.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"
#include "test_units.hpp"

namespace mirage::test {

inline constexpr double kC = physics::kSpeedOfLightMPerS;  // m/s

// The detector kind as the tests print it.
inline const char* detector_name(sensor::DetectorKind k) {
    return k == sensor::DetectorKind::Linear ? "waveform" : "discrete";
}

// Pulse k fires direction dirs[k % n] at t = k · period.
class FanPattern : public sensor::ScanPattern {
  public:
    FanPattern(std::vector<Eigen::Vector3f> dirs, std::int64_t period_ns)
        : dirs_(std::move(dirs)), period_ns_(period_ns) {}
    std::string kind() const override { return "fan"; }
    std::uint64_t pulse_count(core::Nanos d) const override {
        return static_cast<std::uint64_t>((d.count() + period_ns_ - 1) / period_ns_);
    }
    void pulses(std::uint64_t first, std::size_t n, sensor::PulseSpec* out) const override {
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint64_t k = first + i;
            out[i] = {};
            out[i].t_ns = static_cast<std::int64_t>(k) * period_ns_;
            out[i].dir = dirs_[k % dirs_.size()];
            out[i].channel = static_cast<std::uint16_t>(k % dirs_.size());
        }
    }
    double pulse_rate_hz() const override { return 1e9 / double(period_ns_); }
    std::uint32_t channels() const override { return static_cast<std::uint32_t>(dirs_.size()); }
    std::uint32_t group_size() const override { return 1; }

  private:
    std::vector<Eigen::Vector3f> dirs_;
    std::int64_t period_ns_;
};

// A sensor with the given pattern: strong enough that nothing is void unless a test wants it.
inline sensor::SensorModel test_sensor(std::shared_ptr<const sensor::ScanPattern> scan) {
    sensor::SensorModel s;
    s.name = "test";
    s.scan = std::move(scan);
    s.beam.pulse_energy_j = 1e-5;
    s.beam.divergence_rad = 1e-3;
    s.receiver.min_range_m = 0.05;
    s.receiver.max_range_m = 2500.0;
    s.receiver.threshold_gamma = 1.0;
    return s;
}

// Square of side `size` centred at the origin in the plane z = 0 of `frame`.
inline scene::Mesh quad(double size, const Eigen::Affine3d& frame) {
    scene::Mesh m;
    m.name = "quad";
    const double h = size / 2;
    for (auto [x, y] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}})
        m.vertices.push_back((frame * Eigen::Vector3d(x, y, 0)).cast<float>());
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.materials = {0, 0};
    return m;
}

// Plane facing the sensor at distance d along +x, tilted by `tilt` about the z axis.
inline Eigen::Affine3d plane_frame(double d, double tilt) {
    Eigen::Affine3d f = Eigen::Affine3d::Identity();
    f.translate(Eigen::Vector3d(d, 0, 0));
    f.rotate(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitZ()));
    f.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));  // z -> −x
    return f;
}

inline scene::Scene plane_scene(double size, const Eigen::Affine3d& frame,
                                double reflectance = 0.5) {
    scene::Scene s;
    scene::Material m;
    m.name = "grey";
    m.reflectance = reflectance;
    m.classification = 2;
    s.add_material(m);
    s.add_mesh(quad(size, frame));
    return s;
}

class VectorSink : public render::PointSink {
  public:
    void write(std::span<const core::PointRecord> p) override {
        points.insert(points.end(), p.begin(), p.end());
    }
    std::vector<core::PointRecord> points;
};

// Streams points to a callback without keeping them (1e6-sample statistics).
class CallbackSink : public render::PointSink {
  public:
    explicit CallbackSink(std::function<void(const core::PointRecord&)> f) : f_(std::move(f)) {}
    void write(std::span<const core::PointRecord> p) override {
        for (const auto& x : p) f_(x);
    }

  private:
    std::function<void(const core::PointRecord&)> f_;
};

inline Eigen::Vector3f unit(double x, double y, double z) {
    return Eigen::Vector3d(x, y, z).normalized().cast<float>();
}

// A still sensor at the origin: pulses [0, n) 1 µs apart (FanPattern's period), noise off unless
// asked, one thread; the points and the run's counters.
struct Rendered {
    std::vector<core::PointRecord> points;
    render::RenderStats stats;
};
inline Rendered render_still(const scene::Scene& scene, const sensor::SensorModel& sensor,
                             std::uint64_t pulses, bool noise = false) {
    render::EmbreeRenderer r(scene);
    render::RenderOptions o;
    o.noise = noise;
    o.threads = 1;
    o.duration = core::Nanos(static_cast<std::int64_t>(pulses) * 1000);
    VectorSink sink;
    const auto stats =
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, sink);
    return {sink.points, stats};
}

// The photo-electron-weighted variance of arrivals' delays, ns²: the footprint's spread of the
// waveform (docs/time-resolved.md §4).
inline double delay_variance_ns2(const std::vector<physics::Arrival>& a) {
    double m0 = 0, m1 = 0, m2 = 0;
    for (const auto& x : a) {
        const double t = 1e-3 * static_cast<double>(x.delay_ps);
        m0 += x.pe;
        m1 += x.pe * t;
        m2 += x.pe * t * t;
    }
    const double mean = m1 / m0;
    return m2 / m0 - mean * mean;
}

}  // namespace mirage::test
