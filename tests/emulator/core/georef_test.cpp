// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/georef.hpp"

#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "mirage/core/error.hpp"

using namespace mirage::core;

namespace {

std::string message_of(const auto& fn) {
    try {
        fn();
    } catch (const mirage::ConfigError& e) {
        return e.what();
    }
    return "(no ConfigError)";
}

}  // namespace

TEST(Georef, utm32n_wkt_is_wkt1_naming_the_zone) {
    const Georef g = Georef::projected(32632, {500000, 5000000, 0});
    const std::string wkt = g.wkt();
    EXPECT_EQ(wkt.rfind("PROJCS[\"WGS 84 / UTM zone 32N\"", 0), 0u) << wkt;
    EXPECT_NE(wkt.find("UTM zone 32N"), std::string::npos);
    EXPECT_NE(wkt.find("AUTHORITY[\"EPSG\",\"32632\"]"), std::string::npos);
    EXPECT_EQ(wkt.find('\n'), std::string::npos);  // one line
}

TEST(Georef, no_crs_means_identity_world_and_empty_wkt) {
    const Georef g;
    EXPECT_FALSE(g.has_crs());
    EXPECT_EQ(g.wkt(), "");
    EXPECT_EQ(g.world_from_local({1, 2, 3}), Eigen::Vector3d(1, 2, 3));
    EXPECT_THROW(g.local_from_geodetic(45, 9, 0), mirage::ConfigError);
    EXPECT_THROW(g.geodetic_from_local({0, 0, 0}), mirage::ConfigError);
}

TEST(Georef, geodetic_anchor_matches_geographiclib_utm) {
    const Georef g = Georef::geodetic(45, 9, 100);
    EXPECT_EQ(g.epsg(), 32632);
    // Independent implementation (Karney's Krüger series in GeographicLib).
    int zone = 0;
    bool north = false;
    double x = 0, y = 0;
    GeographicLib::UTMUPS::Forward(45, 9, zone, north, x, y);
    EXPECT_EQ(zone, 32);
    std::printf("anchor: %.4f %.4f %.4f (GeographicLib %.4f %.4f)\n", g.anchor().x(),
                g.anchor().y(), g.anchor().z(), x, y);
    EXPECT_NEAR(g.anchor().x(), 500000.0, 1e-6);  // on the central meridian
    EXPECT_NEAR(g.anchor().x(), x, 1e-3);
    EXPECT_NEAR(g.anchor().y(), y, 1e-3);
    EXPECT_DOUBLE_EQ(g.anchor().z(), 100.0);  // ellipsoidal height passes through
}

TEST(Georef, anchor_round_trips_through_geodetic) {
    const Georef g = Georef::geodetic(45, 9, 100);
    EXPECT_LT(g.local_from_geodetic(45, 9, 100).norm(), 1e-3);
    const Eigen::Vector3d llh = g.geodetic_from_local(Eigen::Vector3d::Zero());
    EXPECT_NEAR(llh.x(), 45.0, 1e-9);
    EXPECT_NEAR(llh.y(), 9.0, 1e-9);
    EXPECT_NEAR(llh.z(), 100.0, 1e-6);
}

TEST(Georef, converter_reuses_one_transform_and_matches_the_single_call) {
    const Georef g = Georef::geodetic(45, 9, 100);
    const GeodeticConverter conv(g);
    for (const Eigen::Vector3d& local :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 0, 0), Eigen::Vector3d(-350, 720, 12)}) {
        const Eigen::Vector3d a = conv.geodetic_from_local(local);
        const Eigen::Vector3d b = g.geodetic_from_local(local);
        EXPECT_DOUBLE_EQ(a.x(), b.x());
        EXPECT_DOUBLE_EQ(a.y(), b.y());
        EXPECT_DOUBLE_EQ(a.z(), b.z());
    }
    EXPECT_THROW(GeodeticConverter(Georef{}), mirage::ConfigError);
}

TEST(Georef, point_100m_east_round_trips_within_1mm) {
    const Georef g = Georef::geodetic(45, 9, 100);
    const Eigen::Vector3d local(100, 0, 0);
    const Eigen::Vector3d llh = g.geodetic_from_local(local);
    const Eigen::Vector3d back = g.local_from_geodetic(llh.x(), llh.y(), llh.z());
    std::printf("100 m east round trip error: %.3g m\n", (back - local).norm());
    EXPECT_LT((back - local).norm(), 1e-3);
    // 100 grid metres on the central meridian are 100 / 0.9996 m on the ellipsoid.
    double s12 = 0;
    GeographicLib::Geodesic::WGS84().Inverse(45, 9, llh.x(), llh.y(), s12);
    EXPECT_NEAR(s12, 100.0 / 0.9996, 1e-3);
    EXPECT_NEAR(llh.z(), 100.0, 1e-6);
}

TEST(Georef, batch_conversion_equals_single_points) {
    const Georef g = Georef::geodetic(45, 9, 100);
    const std::vector<Eigen::Vector3d> llh{{45.001, 9.002, 120}, {44.99, 8.99, 80}};
    const auto batch = g.local_from_geodetic(llh);
    ASSERT_EQ(batch.size(), 2u);
    for (std::size_t i = 0; i < llh.size(); ++i) {
        EXPECT_EQ(batch[i], g.local_from_geodetic(llh[i].x(), llh[i].y(), llh[i].z()));
    }
}

TEST(Georef, utm_zone_follows_longitude_hemisphere_and_exceptions) {
    EXPECT_EQ(Georef::geodetic(-33.9, 18.4, 0).epsg(), 32734);  // Cape Town: 34S
    EXPECT_EQ(Georef::geodetic(40.7, -74.0, 0).epsg(), 32618);  // New York: 18N
    EXPECT_EQ(Georef::geodetic(0.0, -179.9, 0).epsg(), 32601);
    EXPECT_EQ(Georef::geodetic(60.0, 5.0, 0).epsg(), 32632);     // Norway exception (not 31)
    EXPECT_EQ(Georef::geodetic(78.0, 10.0, 0).epsg(), 32633);    // Svalbard exception
    EXPECT_EQ(Georef::geodetic(85.0, 0.0, 0).epsg(), 32661);     // UPS north
    EXPECT_EQ(Georef::geodetic(45, 9, 0, 25832).epsg(), 25832);  // explicit EPSG wins
}

TEST(Georef, unknown_or_unprojected_codes_are_config_errors) {
    const std::string unknown = message_of([] { Georef::projected(99999, {0, 0, 0}); });
    EXPECT_EQ(unknown.rfind("georef: EPSG:99999: ", 0), 0u) << unknown;
    std::printf("unknown code: %s\n", unknown.c_str());
    const std::string geographic = message_of([] { Georef::projected(4326, {0, 0, 0}); });
    EXPECT_EQ(geographic.rfind("georef: EPSG:4326: not a projected or geocentric CRS", 0), 0u)
        << geographic;
    const std::string geodetic = message_of([] { Georef::geodetic(45, 9, 0, 99999); });
    EXPECT_EQ(geodetic.rfind("georef: EPSG:99999: ", 0), 0u) << geodetic;
    EXPECT_THROW(Georef::geodetic(91, 0, 0), mirage::ConfigError);
    EXPECT_NO_THROW(Georef::projected(0, {0, 0, 0}));
}
