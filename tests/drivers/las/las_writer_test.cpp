// SPDX-License-Identifier: Apache-2.0
#include "mirage/las/las_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "las_test_points.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_reader.hpp"
#include "test_paths.hpp"

namespace mirage::las {
namespace {

using test::make_points;
using test::TempDir;

class LasRoundTrip : public ::testing::TestWithParam<int> {};

TEST_P(LasRoundTrip, every_field_survives_write_and_read) {
    const auto format = static_cast<std::uint8_t>(GetParam());
    const bool extended = format >= 6;
    const bool rgb = format == 3 || format == 7;
    TempDir dir;
    const std::string path = dir.file("rt.las");
    const auto pts = make_points(5000, 7u + format, extended ? 15 : 7, extended ? 255 : 31);
    {
        LasWriter w(path, core::Georef(), {.point_format = format});
        w.write(std::span(pts).first(1234));
        w.write(std::span(pts).subspan(1234));
        w.close();
        EXPECT_EQ(w.points_written(), pts.size());
        EXPECT_EQ(w.points_rejected(), 0u);
    }
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    const LasHeaderInfo& h = f.header();
    EXPECT_EQ(h.version_major, 1);
    EXPECT_EQ(h.version_minor, 4);
    EXPECT_EQ(h.header_size, 375);
    EXPECT_EQ(h.point_format, format);
    const std::array<int, 8> lengths = {0, 28, 0, 34, 0, 0, 30, 36};
    EXPECT_EQ(h.record_length, lengths[format]);
    ASSERT_EQ(f.points().size(), pts.size());
    double worst_xyz = 0, worst_t = 0;
    for (std::size_t k = 0; k < pts.size(); ++k) {
        const core::PointRecord& e = pts[k];
        const LasPoint& p = f.points()[k];
        worst_xyz =
            std::max({worst_xyz, std::abs(p.x - e.x), std::abs(p.y - e.y), std::abs(p.z - e.z)});
        worst_t = std::max(worst_t, std::abs(p.gps_time - test::expected_adjusted_gps(e.t)));
        ASSERT_EQ(p.intensity, e.intensity) << k;
        ASSERT_EQ(p.return_number, e.return_number) << k;
        ASSERT_EQ(p.number_of_returns, e.number_of_returns) << k;
        ASSERT_EQ(p.classification, e.classification) << k;
        ASSERT_EQ(p.point_source_id, e.point_source_id) << k;
        ASSERT_EQ(p.scan_direction, e.scan_direction) << k;
        ASSERT_EQ(p.edge_of_flight_line, e.edge_of_flight_line) << k;
        if (extended) {
            ASSERT_NEAR(p.scan_angle_deg, e.scan_angle_deg, 0.003 + 1e-4) << k;
        } else {
            ASSERT_EQ(p.scan_angle_deg, std::round(e.scan_angle_deg)) << k;
        }
        ASSERT_EQ(p.red, rgb ? e.red : 0) << k;
        ASSERT_EQ(p.green, rgb ? e.green : 0) << k;
        ASSERT_EQ(p.blue, rgb ? e.blue : 0) << k;
    }
    EXPECT_LE(worst_xyz, 0.0005 + 1e-9);
    EXPECT_LE(worst_t, 1e-6);
    std::printf("format %d: %zu points, worst |dxyz| %.3g m, worst |dt| %.3g s\n", format,
                pts.size(), worst_xyz, worst_t);
}

INSTANTIATE_TEST_SUITE_P(Formats, LasRoundTrip, ::testing::Values(1, 3, 6, 7));

TEST(LasWriter, rounds_to_nearest_instead_of_truncating) {
    TempDir dir;
    const std::string path = dir.file("round.las");
    std::vector<core::PointRecord> pts(4);
    pts[0].x = 0.0006;   // truncation would store 0
    pts[1].x = -0.0006;  // truncation would store 0
    pts[2].x = 0.0004;
    pts[3].x = -0.0014;
    for (auto& p : pts) p.t = test::test_time(0);
    {
        LasWriter w(path, core::Georef(), {.point_format = 6, .scale = 0.001});
        w.write(pts);
    }
    const LasFile f = LasFile::read(path);
    ASSERT_EQ(f.points().size(), 4u);
    EXPECT_EQ(f.header().offset[0], 0.0);
    EXPECT_EQ(f.points()[0].raw_x, 1);
    EXPECT_EQ(f.points()[1].raw_x, -1);
    EXPECT_EQ(f.points()[2].raw_x, 0);
    EXPECT_EQ(f.points()[3].raw_x, -1);
    EXPECT_DOUBLE_EQ(f.points()[0].x, 0.001);
    EXPECT_DOUBLE_EQ(f.points()[1].x, -0.001);
}

TEST(LasWriter, utm_anchor_round_trips_within_half_a_millimetre) {
    TempDir dir;
    const std::string path = dir.file("utm.las");
    const Eigen::Vector3d anchor(500000.3217, 4500000.7781, 251.25);
    const core::Georef georef = core::Georef::projected(32632, anchor);
    auto pts = make_points(20000, 11, 5, 31, 1500.0);
    {
        LasWriter w(path, georef, {.point_format = 6});
        const auto off = w.offset();
        EXPECT_EQ(off[0], 500000.0);
        EXPECT_EQ(off[1], 4500000.0);
        EXPECT_EQ(off[2], 0.0);
        w.write(pts);
    }
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    ASSERT_EQ(f.points().size(), pts.size());
    double worst = 0;
    for (std::size_t k = 0; k < pts.size(); ++k) {
        const Eigen::Vector3d world = anchor + Eigen::Vector3d(pts[k].x, pts[k].y, pts[k].z);
        const LasPoint& p = f.points()[k];
        worst = std::max({worst, std::abs(p.x - world.x()), std::abs(p.y - world.y()),
                          std::abs(p.z - world.z())});
    }
    EXPECT_LE(worst, 0.0005 + 1e-9);
    std::printf("UTM anchor: worst |d| %.3g m over %zu points\n", worst, pts.size());
}

TEST(LasWriter, counts_by_return_and_bounds_match_the_points) {
    TempDir dir;
    for (const std::uint8_t format : std::array<std::uint8_t, 2>{3, 7}) {
        const std::string path = dir.file("counts" + std::to_string(format) + ".las");
        // Returns 1,1,1,2,2,3,6 ; known extremes.
        const int returns[] = {1, 1, 1, 2, 2, 3, 6};
        std::vector<core::PointRecord> pts;
        for (int k = 0; k < 7; ++k) {
            core::PointRecord p;
            p.x = -10.0 + k;
            p.y = 3.25 * k;
            p.z = k == 4 ? -7.5 : 0.125 * k;
            p.t = test::test_time(static_cast<std::uint64_t>(k));
            p.return_number = static_cast<std::uint8_t>(returns[k]);
            p.number_of_returns = 6;
            pts.push_back(p);
        }
        {
            LasWriter w(path, core::Georef(), {.point_format = format});
            w.write(pts);
        }
        const LasFile f = LasFile::read(path);
        EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
        const LasHeaderInfo& h = f.header();
        EXPECT_EQ(h.point_count, 7u);
        const std::array<std::uint64_t, 15> want = {3, 2, 1, 0, 0, 1};
        EXPECT_EQ(h.points_by_return, want);
        if (format < 6) {
            EXPECT_EQ(h.legacy_point_count, 7u);
            EXPECT_EQ(h.legacy_points_by_return, (std::array<std::uint32_t, 5>{3, 2, 1, 0, 0}));
        } else {
            EXPECT_EQ(h.legacy_point_count, 0u);
            EXPECT_EQ(h.legacy_points_by_return, (std::array<std::uint32_t, 5>{}));
        }
        EXPECT_DOUBLE_EQ(h.min[0], -10.0);
        EXPECT_DOUBLE_EQ(h.max[0], -4.0);
        EXPECT_DOUBLE_EQ(h.min[1], 0.0);
        EXPECT_DOUBLE_EQ(h.max[1], 19.5);
        EXPECT_DOUBLE_EQ(h.min[2], -7.5);
        EXPECT_DOUBLE_EQ(h.max[2], 0.75);
    }
}

TEST(LasWriter, wkt_vlr_and_global_encoding_follow_the_crs) {
    TempDir dir;
    const core::Georef utm = core::Georef::projected(32632, Eigen::Vector3d(500000, 4500000, 0));
    const auto pts = make_points(10, 3);
    for (const std::uint8_t format : std::array<std::uint8_t, 4>{1, 3, 6, 7}) {
        const std::string with = dir.file("crs" + std::to_string(format) + ".las");
        const std::string without = dir.file("nocrs" + std::to_string(format) + ".las");
        {
            LasWriter a(with, utm, {.point_format = format});
            a.write(pts);
            LasWriter b(without, core::Georef(), {.point_format = format});
            b.write(pts);
        }
        const LasFile fa = LasFile::read(with);
        EXPECT_TRUE(fa.validate().empty()) << ::testing::PrintToString(fa.validate());
        EXPECT_EQ(fa.header().global_encoding, 0x11) << int(format);
        EXPECT_EQ(fa.header().vlr_count, 1u);
        EXPECT_TRUE(fa.header().has_wkt_vlr);
        EXPECT_EQ(fa.header().wkt, utm.wkt());
        EXPECT_NE(fa.header().wkt.find("32N"), std::string::npos) << fa.header().wkt;
        EXPECT_EQ(fa.header().offset_to_points, 375u + 54u + utm.wkt().size() + 1u);

        const LasFile fb = LasFile::read(without);
        EXPECT_TRUE(fb.validate().empty()) << ::testing::PrintToString(fb.validate());
        // Formats 6–10 carry the WKT bit even without a CRS (LAS 1.4; PDAL requires it).
        EXPECT_EQ(fb.header().global_encoding, format >= 6 ? 0x11 : 0x01) << int(format);
        EXPECT_EQ(fb.header().vlr_count, 0u);
        EXPECT_EQ(fb.header().offset_to_points, 375u);
    }
}

TEST(LasWriter, same_points_give_byte_identical_files) {
    TempDir dir;
    const auto pts = make_points(3000, 5);
    const core::Georef utm = core::Georef::projected(32632, Eigen::Vector3d(500000, 4500000, 0));
    for (const char* name : {"a.las", "b.las"}) {
        LasWriter w(dir.file(name), utm, {.point_format = 7, .buffer_bytes = 4096});
        w.write(pts);
        w.close();
    }
    const auto a = test::file_bytes(dir.file("a.las"));
    const auto b = test::file_bytes(dir.file("b.las"));
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a, b);
    // Creation date is the fixed option, not today's.
    EXPECT_EQ(a[90] | a[91] << 8, 1);
    EXPECT_EQ(a[92] | a[93] << 8, 2025);
}

// The render workers encode chunks in parallel (encode) and one thread writes them in order
// (write_encoded), mixed with plain writes: the file must be the one write() alone makes, with
// the same rejected and remapped counts.
TEST(LasWriter, chunks_encoded_on_other_threads_give_the_file_write_gives) {
    TempDir dir;
    for (const int format : {1, 3, 6, 7}) {
        auto pts = make_points(2000, 17, 5, 60);  // classes up to 60: formats 1/3 remap some
        pts[10].x = 3.0e6;                        // not representable: rejected
        pts[1500].z = std::nan("");
        const core::Georef utm =
            core::Georef::projected(32632, Eigen::Vector3d(500000, 4500000, 0));
        const LasWriterOptions opt{.point_format = static_cast<std::uint8_t>(format),
                                   .buffer_bytes = 4096};
        const std::string plain = dir.file("plain.las"), mixed = dir.file("mixed.las");
        std::uint64_t rejected = 0, remapped = 0;
        {
            LasWriter w(plain, utm, opt);
            w.write(pts);
            rejected = w.points_rejected();
            remapped = w.classifications_remapped();
        }
        ASSERT_EQ(rejected, 2u);
        if (format < 6) {
            ASSERT_GT(remapped, 0u);
        }
        {
            LasWriter w(mixed, utm, opt);
            w.write(std::span(pts).first(300));  // buffered, must precede the chunks
            std::vector<EncodedRecords> chunks(4);
            std::vector<std::thread> threads;
            for (std::size_t c = 0; c < chunks.size(); ++c)
                threads.emplace_back([&, c] {
                    const auto part = std::span(pts).subspan(300 + 400 * c, 400);
                    w.encode(part.first(150), chunks[c]);  // two calls append
                    w.encode(part.subspan(150), chunks[c]);
                });
            for (auto& t : threads) t.join();
            for (const auto& chunk : chunks) w.write_encoded(chunk);
            w.write(std::span(pts).subspan(1900));
            EXPECT_EQ(w.points_rejected(), rejected);
            EXPECT_EQ(w.classifications_remapped(), remapped);
            EXPECT_EQ(w.points_written(), pts.size() - rejected);
        }
        EXPECT_EQ(test::file_bytes(plain), test::file_bytes(mixed)) << "format " << format;
        const LasFile f = LasFile::read(mixed);
        EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
        EXPECT_EQ(f.header().point_count, pts.size() - rejected);
    }
}

TEST(LasWriter, encoded_records_of_another_format_are_refused) {
    TempDir dir;
    const auto pts = make_points(10, 3);
    LasWriter w6(dir.file("a.las"), core::Georef(), {.point_format = 6});
    LasWriter w7(dir.file("b.las"), core::Georef(), {.point_format = 7});
    EncodedRecords rec;
    w7.encode(pts, rec);
    EXPECT_EQ(rec.stats.count, 10u);
    EXPECT_EQ(rec.bytes.size(), 10u * 36u);
    EXPECT_THROW(w6.write_encoded(rec), IoError);
    rec.clear();
    EXPECT_TRUE(rec.bytes.empty());
    EXPECT_EQ(rec.stats.count, 0u);
}

TEST(LasWriter, points_that_do_not_fit_int32_are_rejected_and_counted) {
    TempDir dir;
    const std::string path = dir.file("reject.las");
    auto pts = make_points(10, 9);
    pts[2].x = 3.0e6;  // 3000 km from the offset: > 2^31 mm
    pts[5].y = std::nan("");
    pts[7].z = -std::numeric_limits<double>::infinity();
    {
        LasWriter w(path, core::Georef(), {.point_format = 6});
        w.write(pts);
        EXPECT_EQ(w.points_rejected(), 3u);
        EXPECT_EQ(w.points_written(), 7u);
    }
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    ASSERT_EQ(f.points().size(), 7u);
    EXPECT_NEAR(f.points()[2].x, pts[3].x, 0.0005);
}

TEST(LasWriter, legacy_formats_map_classes_above_31_and_clamp_the_scan_angle) {
    TempDir dir;
    auto pts = make_points(3, 4);
    pts[0].classification = 40;
    pts[1].classification = 31;
    pts[0].scan_angle_deg = 120.0f;
    pts[1].scan_angle_deg = -95.4f;
    pts[2].scan_angle_deg = 12.6f;
    {
        LasWriter w(dir.file("c1.las"), core::Georef(), {.point_format = 1});
        w.write(pts);
        EXPECT_EQ(w.classifications_remapped(), 1u);
        LasWriter w6(dir.file("c6.las"), core::Georef(), {.point_format = 6});
        w6.write(pts);
        EXPECT_EQ(w6.classifications_remapped(), 0u);
    }
    const LasFile f1 = LasFile::read(dir.file("c1.las"));
    EXPECT_EQ(f1.points()[0].classification, 1);
    EXPECT_EQ(f1.points()[1].classification, 31);
    EXPECT_EQ(f1.points()[0].scan_angle_deg, 90.0f);
    EXPECT_EQ(f1.points()[1].scan_angle_deg, -90.0f);
    EXPECT_EQ(f1.points()[2].scan_angle_deg, 13.0f);
    const LasFile f6 = LasFile::read(dir.file("c6.las"));
    EXPECT_EQ(f6.points()[0].classification, 40);
    EXPECT_NEAR(f6.points()[0].scan_angle_deg, 120.0, 0.003);
    EXPECT_NEAR(f6.points()[1].scan_angle_deg, -95.4, 0.003);
}

TEST(LasWriter, missing_folder_throws_io_error_naming_the_path) {
    const std::string path = "/nonexistent-mirage-folder/sub/out.las";
    try {
        LasWriter w(path, core::Georef());
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("las writer '", 0), 0u) << e.what();
    }
}

TEST(LasWriter, unsupported_format_is_a_config_error) {
    TempDir dir;
    EXPECT_THROW(LasWriter(dir.file("x.las"), core::Georef(), {.point_format = 2}), ConfigError);
    EXPECT_THROW(LasWriter(dir.file("x.las"), core::Georef(), {.scale = 0.0}), ConfigError);
}

TEST(LasWriter, empty_file_is_valid) {
    TempDir dir;
    { LasWriter w(dir.file("empty.las"), core::Georef()); }
    const LasFile f = LasFile::read(dir.file("empty.las"));
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().point_count, 0u);
    EXPECT_EQ(f.file_size(), 375u);
}

TEST(LasWriter, header_on_disk_matches_each_flush) {
    TempDir dir;
    const std::string path = dir.file("flush.las");
    const auto pts = make_points(250, 2);
    LasWriter w(path, core::Georef(), {.point_format = 6, .buffer_bytes = 30 * 100});
    w.write(pts);  // 2 flushes of 100 records, 50 buffered
    EXPECT_EQ(w.points_flushed(), 200u);
    const LasFile mid = LasFile::read(path);
    EXPECT_TRUE(mid.validate().empty()) << ::testing::PrintToString(mid.validate());
    EXPECT_EQ(mid.header().point_count, 200u);
    w.close();
    EXPECT_EQ(LasFile::read(path).header().point_count, 250u);
}

// A header that cannot be written fails naming the file; a failed regular file is removed, a
// device never (the writer once deleted /dev/full itself).
TEST(LasWriter, a_failed_header_never_removes_a_device) {
    if (!std::filesystem::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full";
    try {
        LasWriter w("/dev/full", core::Georef(), {});
        FAIL() << "wrote a header to /dev/full";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("'/dev/full': cannot write header"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
}

}  // namespace
}  // namespace mirage::las
