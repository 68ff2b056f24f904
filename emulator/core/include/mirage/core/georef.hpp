// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace mirage::core {

// How far from the anchor, per axis, a sensor may be: Embree's float32 coordinates step by more
// than 1 mm beyond 2^14 m, and 1 mm is the finest range unit any encoder writes (Ouster); a
// sensor further out is almost always a trajectory or INS in another frame than the scene's
// (docs/conventions.md §3).
inline constexpr double kLocalRangeM = 16384;

// Georeference of a scene: a double-precision anchor in a projected or geocentric CRS (EPSG).
// Geometry and poses are float32/double *relative to the anchor* ("local" frame, metres,
// x = grid east, y = grid north, z = up), which keeps float32 geometry within ~1 km of zero
// however large the projected coordinates are (docs/physics.md §4.8).
// A geodetic anchor (lat/lon/h) is converted once to its UTM zone (EPSG 326xx/327xx, with the
// Norway/Svalbard exceptions; UPS 32661/32761 beyond 84°N / 80°S) unless an EPSG code is given.
// Heights stay ellipsoidal (WGS84, EPSG:4979) for 2-D projected CRSs.
// Errors: ConfigError "georef: EPSG:<n>: <reason>" for unknown or non-projected codes.
// A scene without a georeference uses EPSG 0 and anchor (0, 0, 0).
// Load-time only (PROJ calls); not for per-pulse use.
class Georef {
  public:
    Georef() = default;
    static Georef projected(int epsg, const Eigen::Vector3d& anchor);
    static Georef geodetic(double lat_deg, double lon_deg, double h_m, int epsg = 0);

    int epsg() const { return epsg_; }
    const Eigen::Vector3d& anchor() const { return anchor_; }
    bool has_crs() const { return epsg_ != 0; }

    // World (projected) <-> local.
    Eigen::Vector3d world_from_local(const Eigen::Vector3d& local) const { return anchor_ + local; }
    Eigen::Vector3d local_from_world(const Eigen::Vector3d& world) const { return world - anchor_; }
    // WGS84 geodetic (degrees, ellipsoidal height) -> local. Throws ConfigError without a CRS.
    Eigen::Vector3d local_from_geodetic(double lat_deg, double lon_deg, double h_m) const;
    // Many points with one PROJ setup (each single call builds its own, ~10 ms): elements are
    // (lat_deg, lon_deg, h_m). Used by load_trajectory_csv.
    std::vector<Eigen::Vector3d> local_from_geodetic(
        const std::vector<Eigen::Vector3d>& lat_lon_h) const;
    // Local -> WGS84 geodetic (lat, lon in degrees, h in m).
    Eigen::Vector3d geodetic_from_local(const Eigen::Vector3d& local) const;
    // OGC WKT (WKT1 as LAS 1.4 readers expect) of the CRS, from PROJ; empty without a CRS.
    std::string wkt() const;

  private:
    int epsg_ = 0;
    Eigen::Vector3d anchor_{Eigen::Vector3d::Zero()};
};

// Local -> WGS84 geodetic with the PROJ set-up done once (a single Georef::geodetic_from_local
// call builds its own, ~10 ms): for per-packet conversions on a streaming thread. Not
// thread-safe; one per thread.
class GeodeticConverter {
  public:
    explicit GeodeticConverter(const Georef& georef);  // throws ConfigError without a CRS
    ~GeodeticConverter();
    GeodeticConverter(const GeodeticConverter&) = delete;
    GeodeticConverter& operator=(const GeodeticConverter&) = delete;
    Eigen::Vector3d geodetic_from_local(const Eigen::Vector3d& local) const;  // (lat, lon, h)

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mirage::core
