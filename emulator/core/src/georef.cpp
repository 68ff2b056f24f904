// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/georef.hpp"

#include <proj.h>

#include <GeographicLib/UTMUPS.hpp>
#include <cmath>
#include <memory>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::core {

// The types of GeodeticConverter::Impl's fields live in a named namespace: a field whose type
// is in an anonymous namespace is -Wsubobject-linkage once this file is not the main file
// (unity builds).
namespace georef_detail {

// One PROJ context per call: contexts are not thread-safe, and georeferencing happens at
// load time only, so there is nothing to gain from sharing one.
class ProjContext {
  public:
    ProjContext() : ctx_(proj_context_create()) {
        if (ctx_ == nullptr) throw ConfigError("georef: cannot create a PROJ context");
        // Capture PROJ's messages instead of letting it print to stderr; the last one names
        // the problem better than the error code ("crs not found").
        proj_log_func(ctx_, this, [](void* self, int, const char* msg) {
            static_cast<ProjContext*>(self)->last_message_ = msg ? msg : "";
        });
    }
    ~ProjContext() { proj_context_destroy(ctx_); }
    ProjContext(const ProjContext&) = delete;
    ProjContext& operator=(const ProjContext&) = delete;

    PJ_CONTEXT* get() const { return ctx_; }

    std::string error() const {
        std::string msg = last_message_;
        // Drop PROJ's "function_name: " prefix.
        if (auto colon = msg.find(": ");
            colon != std::string::npos && msg.find(' ') > colon && colon > 0) {
            msg = msg.substr(colon + 2);
        }
        if (msg.empty()) {
            const int err = proj_context_errno(ctx_);
            const char* s = err != 0 ? proj_context_errno_string(ctx_, err) : nullptr;
            msg = s ? s : "unknown PROJ error";
        }
        return msg;
    }

  private:
    PJ_CONTEXT* ctx_;
    std::string last_message_;
};

struct PjDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using PjPtr = std::unique_ptr<PJ, PjDeleter>;

}  // namespace georef_detail

using georef_detail::PjPtr;
using georef_detail::ProjContext;

namespace {

[[noreturn]] void fail(int epsg, const std::string& why) {
    throw ConfigError("georef: EPSG:" + std::to_string(epsg) + ": " + why);
}

PjPtr create_crs(ProjContext& ctx, int epsg) {
    if (epsg <= 0) fail(epsg, "not a valid EPSG code");
    const std::string code = std::to_string(epsg);
    PjPtr crs{
        proj_create_from_database(ctx.get(), "EPSG", code.c_str(), PJ_CATEGORY_CRS, 0, nullptr)};
    if (!crs) fail(epsg, ctx.error());
    return crs;
}

// Anchors and the local frame are metres on Cartesian axes, so only projected CRSs (optionally
// with a vertical CRS) and geocentric (ECEF, e.g. EPSG:4978) CRSs make sense.
void require_projected(ProjContext& ctx, int epsg, PJ* crs) {
    PJ_TYPE type = proj_get_type(crs);
    if (type == PJ_TYPE_COMPOUND_CRS) {
        PjPtr horizontal{proj_crs_get_sub_crs(ctx.get(), crs, 0)};
        type = horizontal ? proj_get_type(horizontal.get()) : PJ_TYPE_UNKNOWN;
    }
    if (type != PJ_TYPE_PROJECTED_CRS && type != PJ_TYPE_GEOCENTRIC_CRS) {
        fail(epsg, "not a projected or geocentric CRS (the anchor and local frame are in metres)");
    }
}

// WGS84 (lat, lon, ellipsoidal h) <-> the projected CRS, lon/lat order normalised to x/y.
PjPtr create_transform(ProjContext& ctx, int epsg) {
    const std::string target = "EPSG:" + std::to_string(epsg);
    PjPtr raw{proj_create_crs_to_crs(ctx.get(), "EPSG:4979", target.c_str(), nullptr)};
    if (!raw) fail(epsg, "no transformation from WGS84 (EPSG:4979): " + ctx.error());
    PjPtr norm{proj_normalize_for_visualization(ctx.get(), raw.get())};
    if (!norm) fail(epsg, "cannot normalise axis order: " + ctx.error());
    return norm;
}

void check_geodetic(int epsg, double lat_deg, double lon_deg, double h_m) {
    if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg) || !std::isfinite(h_m) ||
        std::abs(lat_deg) > 90.0 || std::abs(lon_deg) > 360.0) {
        fail(epsg, "geodetic position (lat " + std::to_string(lat_deg) + ", lon " +
                       std::to_string(lon_deg) + ", h " + std::to_string(h_m) + ") out of range");
    }
}

Eigen::Vector3d forward(ProjContext& ctx, PJ* t, int epsg, const Eigen::Vector3d& llh) {
    check_geodetic(epsg, llh.x(), llh.y(), llh.z());
    proj_errno_reset(t);
    const PJ_COORD out = proj_trans(t, PJ_FWD, proj_coord(llh.y(), llh.x(), llh.z(), 0.0));
    const Eigen::Vector3d xyz{out.xyz.x, out.xyz.y, out.xyz.z};
    if (!xyz.allFinite()) {
        fail(epsg, "cannot project lat " + std::to_string(llh.x()) + ", lon " +
                       std::to_string(llh.y()) + ": " + ctx.error());
    }
    return xyz;
}

}  // namespace

Georef Georef::projected(int epsg, const Eigen::Vector3d& anchor) {
    if (!anchor.allFinite()) fail(epsg, "anchor is not finite");
    Georef g;
    if (epsg != 0) {
        ProjContext ctx;
        PjPtr crs = create_crs(ctx, epsg);
        require_projected(ctx, epsg, crs.get());
    }
    g.epsg_ = epsg;
    g.anchor_ = anchor;
    return g;
}

Georef Georef::geodetic(double lat_deg, double lon_deg, double h_m, int epsg) {
    check_geodetic(epsg, lat_deg, lon_deg, h_m);
    if (epsg == 0) {
        // GeographicLib applies the Norway / Svalbard zone exceptions; zone 0 means UPS.
        const int zone = GeographicLib::UTMUPS::StandardZone(lat_deg, lon_deg);
        const bool north = lat_deg >= 0.0;
        epsg = zone == 0 ? (north ? 32661 : 32761) : (north ? 32600 : 32700) + zone;
    }
    ProjContext ctx;
    PjPtr crs = create_crs(ctx, epsg);
    require_projected(ctx, epsg, crs.get());
    PjPtr t = create_transform(ctx, epsg);
    Georef g;
    g.epsg_ = epsg;
    g.anchor_ = forward(ctx, t.get(), epsg, {lat_deg, lon_deg, h_m});
    return g;
}

Eigen::Vector3d Georef::local_from_geodetic(double lat_deg, double lon_deg, double h_m) const {
    return local_from_geodetic(std::vector<Eigen::Vector3d>{{lat_deg, lon_deg, h_m}}).front();
}

std::vector<Eigen::Vector3d> Georef::local_from_geodetic(
    const std::vector<Eigen::Vector3d>& lat_lon_h) const {
    if (!has_crs()) {
        throw ConfigError("georef: geodetic coordinates need a CRS, but no EPSG code is set");
    }
    ProjContext ctx;
    PjPtr t = create_transform(ctx, epsg_);
    std::vector<Eigen::Vector3d> out;
    out.reserve(lat_lon_h.size());
    for (const auto& llh : lat_lon_h) out.push_back(forward(ctx, t.get(), epsg_, llh) - anchor_);
    return out;
}

Eigen::Vector3d Georef::geodetic_from_local(const Eigen::Vector3d& local) const {
    return GeodeticConverter(*this).geodetic_from_local(local);
}

struct GeodeticConverter::Impl {
    Georef georef;
    ProjContext ctx;
    PjPtr transform;
};

GeodeticConverter::GeodeticConverter(const Georef& georef) : impl_(std::make_unique<Impl>()) {
    if (!georef.has_crs()) {
        throw ConfigError("georef: geodetic coordinates need a CRS, but no EPSG code is set");
    }
    impl_->georef = georef;
    impl_->transform = create_transform(impl_->ctx, georef.epsg());
}

GeodeticConverter::~GeodeticConverter() = default;

Eigen::Vector3d GeodeticConverter::geodetic_from_local(const Eigen::Vector3d& local) const {
    PJ* t = impl_->transform.get();
    const Eigen::Vector3d w = impl_->georef.world_from_local(local);
    proj_errno_reset(t);
    const PJ_COORD out = proj_trans(t, PJ_INV, proj_coord(w.x(), w.y(), w.z(), 0.0));
    const Eigen::Vector3d llh{out.xyz.y, out.xyz.x, out.xyz.z};  // lon/lat -> lat, lon
    if (!llh.allFinite())
        fail(impl_->georef.epsg(), "cannot unproject local point: " + impl_->ctx.error());
    return llh;
}

std::string Georef::wkt() const {
    if (!has_crs()) return {};
    ProjContext ctx;
    PjPtr crs = create_crs(ctx, epsg_);
    // WKT1 in GDAL's flavour is what LAS 1.4 readers (PDAL, LAStools, GDAL) parse.
    const char* const options[] = {"MULTILINE=NO", nullptr};
    const char* text = proj_as_wkt(ctx.get(), crs.get(), PJ_WKT1_GDAL, options);
    if (text == nullptr) fail(epsg_, "no WKT1 representation: " + ctx.error());
    return text;
}

}  // namespace mirage::core
