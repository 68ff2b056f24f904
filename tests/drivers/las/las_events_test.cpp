// SPDX-License-Identifier: Apache-2.0
// Photon-event extra bytes (docs/photon-counting.md §4): pixel, event kind and time of flight
// after each record, alone or after the echo fields, described by one Extra Bytes VLR, read back.
#include <gtest/gtest.h>

#include "las_test_points.hpp"
#include "mirage/las/las_reader.hpp"
#include "mirage/las/las_writer.hpp"
#include "test_paths.hpp"

namespace mirage::las {
namespace {

TEST(LasEvents, event_fields_survive_write_and_read) {
    for (const bool echo : {false, true})
        for (const int format : {1, 6, 7}) {
            test::TempDir dir;
            const std::string path = dir.file("e.las");
            auto pts = test::make_points(500, 11u, 5, 31);
            for (std::size_t k = 0; k < pts.size(); ++k) {
                pts[k].pixel = static_cast<std::uint32_t>(k * 7919 % 76800);
                pts[k].event = static_cast<std::uint8_t>(1 + k % 4);
                pts[k].range_m = 1200.0f + static_cast<float>(k) * 0.01f;
                pts[k].amplitude = static_cast<float>(k);
            }
            LasWriterOptions o;
            o.point_format = static_cast<std::uint8_t>(format);
            o.echo_fields = echo;
            o.event_fields = true;
            {
                LasWriter w(path, core::Georef(), o);
                w.write(pts);
                w.close();
            }
            const LasFile f = LasFile::read(path);
            EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
            const auto& names = f.header().extra_bytes_names;
            ASSERT_EQ(names.size(), echo ? 6u : 3u);
            EXPECT_EQ(names.back(), "time of flight");
            ASSERT_EQ(f.points().size(), pts.size());
            for (std::size_t k = 0; k < pts.size(); ++k) {
                const LasPoint& p = f.points()[k];
                ASSERT_EQ(p.pixel, pts[k].pixel);
                ASSERT_EQ(p.event, pts[k].event);
                ASSERT_NEAR(p.time_of_flight_ns, double(pts[k].range_m) * 2e9 / 299792458.0, 1e-9);
                ASSERT_EQ(p.amplitude, echo ? pts[k].amplitude : 0.0f);
            }
        }
}

}  // namespace
}  // namespace mirage::las
