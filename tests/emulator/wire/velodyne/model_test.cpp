// SPDX-License-Identifier: Apache-2.0
// Model descriptors against the spec (docs/wire-formats.md §1.3–§1.7) and the sensor presets.
#include "mirage/velodyne/model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "mirage/sensor/spinning.hpp"

namespace mirage::velodyne {
namespace {

TEST(VelodyneModel, product_ids_and_distance_resolution_follow_the_spec) {
    EXPECT_EQ(descriptor(Model::Vlp16).product_id, 0x22);
    EXPECT_EQ(descriptor(Model::Vlp16HiRes).product_id, 0x24);
    EXPECT_EQ(descriptor(Model::Vlp32c).product_id, 0x28);
    EXPECT_EQ(descriptor(Model::Hdl32e).product_id, 0x21);
    EXPECT_TRUE(descriptor(Model::Hdl64eS3).hdl64_status);
    EXPECT_DOUBLE_EQ(descriptor(Model::Vlp32c).distance_lsb_m, 0.004);
    for (Model m : {Model::Vlp16, Model::Vlp16HiRes, Model::Hdl32e, Model::Hdl64eS3})
        EXPECT_DOUBLE_EQ(descriptor(m).distance_lsb_m, 0.002);
    for (Model m : kAllModels) {
        EXPECT_EQ(descriptor(m).rpm_min, 300);
        EXPECT_EQ(descriptor(m).rpm_max, 1200);
        EXPECT_EQ(model_from_name(descriptor(m).name), m);
    }
    EXPECT_EQ(model_from_product_id(0x63), std::nullopt);
    EXPECT_EQ(static_cast<int>(ReturnMode::Strongest), 0x37);
    EXPECT_EQ(static_cast<int>(ReturnMode::Last), 0x38);
    EXPECT_EQ(static_cast<int>(ReturnMode::Dual), 0x39);
}

// The packets must describe the pattern the pipeline renders: period, firing offsets and angles
// of every laser equal the sensor preset's.
TEST(VelodyneModel, descriptors_match_the_sensor_presets_laser_by_laser) {
    for (Model m : kAllModels) {
        const ModelDescriptor& md = descriptor(m);
        SCOPED_TRACE(std::string(md.name));
        const sensor::SensorModel s = sensor::preset(std::string(md.name));
        const auto* sp = dynamic_cast<const sensor::SpinningPattern*>(s.scan.get());
        ASSERT_NE(sp, nullptr);
        const auto& cfg = sp->config();
        ASSERT_EQ(static_cast<int>(cfg.lasers.size()), md.lasers);
        EXPECT_EQ(cfg.sequence_period_ns, static_cast<double>(md.sequence_period_ns));
        EXPECT_DOUBLE_EQ(sp->rpm(), md.rpm_default);
        for (int l = 0; l < md.lasers; ++l) {
            const auto& a = cfg.lasers[static_cast<std::size_t>(l)];
            const auto& b = md.laser[static_cast<std::size_t>(l)];
            EXPECT_EQ(std::llround(a.firing_offset_ns), b.firing_offset_ns) << "laser " << l;
            EXPECT_EQ(a.elevation_deg, b.elevation_deg) << "laser " << l;
            EXPECT_EQ(a.azimuth_offset_deg, b.azimuth_offset_deg) << "laser " << l;
        }
    }
}

TEST(VelodyneModel, angle_tables_hold_the_published_values) {
    // §1.7 spot values.
    const auto& v16 = descriptor(Model::Vlp16).laser;
    EXPECT_EQ(v16[0].elevation_deg, -15);
    EXPECT_EQ(v16[1].elevation_deg, 1);
    EXPECT_EQ(v16[15].elevation_deg, 15);
    EXPECT_EQ(v16[15].firing_offset_ns, 34'560);
    EXPECT_EQ(descriptor(Model::Vlp16HiRes).laser[13].elevation_deg, 8.667);
    const auto& v32 = descriptor(Model::Vlp32c).laser;
    EXPECT_EQ(v32[0].elevation_deg, -25.0);
    EXPECT_EQ(v32[14].azimuth_offset_deg, 4.2);   // manual δ of laser 14
    EXPECT_EQ(v32[15].azimuth_offset_deg, -1.4);  // laser 15
    EXPECT_EQ(v32[31].firing_offset_ns, 34'560);
    EXPECT_EQ(v32[30].firing_offset_ns, 34'560);
    const auto& h32 = descriptor(Model::Hdl32e).laser;
    EXPECT_EQ(h32[0].elevation_deg, -30.67);
    EXPECT_EQ(h32[31].elevation_deg, 10.67);
    EXPECT_EQ(h32[31].firing_offset_ns, 35'712);
    // HDL-64E S3 xiesc yaml, laser 0 and 63 (radians in the file).
    const auto& h64 = descriptor(Model::Hdl64eS3).laser;
    constexpr double kDeg = 3.14159265358979323846 / 180.0;
    EXPECT_NEAR(h64[0].elevation_deg * kDeg, -0.1261818455292898, 1e-15);
    EXPECT_NEAR(-h64[0].azimuth_offset_deg * kDeg, -0.07648247457737148, 1e-15);
    EXPECT_NEAR(h64[63].elevation_deg * kDeg, -0.2079266762969834, 1e-15);
    // Upper laser u and lower laser 32 + u fire together; the cycle ends before 48 µs.
    for (int u = 0; u < 32; ++u)
        EXPECT_EQ(h64[static_cast<std::size_t>(u)].firing_offset_ns,
                  h64[static_cast<std::size_t>(32 + u)].firing_offset_ns);
    EXPECT_EQ(h64[1].firing_offset_ns, 1'260);
    EXPECT_EQ(h64[31].firing_offset_ns, 45'660);
}

TEST(VelodyneModel, block_layout_is_a_bijection_onto_the_packet_slots) {
    for (Model m : kAllModels)
        for (ReturnMode mode : kAllReturnModes) {
            const ModelDescriptor& md = descriptor(m);
            SCOPED_TRACE(std::string(md.name) + " " + to_string(mode));
            const int rets = mode == ReturnMode::Dual ? 2 : 1;
            std::set<std::pair<int, int>> used;
            for (int q = 0; q < md.sequences_per_packet(mode); ++q)
                for (int l = 0; l < md.lasers; ++l)
                    for (int r = 0; r < rets; ++r) {
                        const BlockSlot bs = md.locate(mode, q, l, r);
                        ASSERT_GE(bs.block, 0);
                        ASSERT_LT(bs.block, 12);
                        ASSERT_LT(bs.slot, 32);
                        EXPECT_TRUE(used.insert({bs.block, bs.slot}).second);
                        const auto si = md.slot_info(mode, bs.block, bs.slot);
                        EXPECT_EQ(si.sequence, q);
                        EXPECT_EQ(si.laser, l);
                        EXPECT_EQ(si.ret, r);
                    }
            EXPECT_EQ(used.size(), 384u);
        }
    // §1.5: VLP-16 dual keeps 2 sequences per block, 12 per packet; HDL-64E dual quads.
    EXPECT_EQ(descriptor(Model::Vlp16).sequences_per_packet(ReturnMode::Dual), 12);
    EXPECT_EQ(descriptor(Model::Hdl64eS3).sequences_per_packet(ReturnMode::Dual), 3);
    EXPECT_EQ(descriptor(Model::Hdl64eS3).locate(ReturnMode::Dual, 1, 40, 1).block, 7);
    EXPECT_EQ(descriptor(Model::Hdl64eS3).block_flag(7), 0xDDFF);
    EXPECT_EQ(descriptor(Model::Vlp16).locate(ReturnMode::Strongest, 3, 5, 0).slot, 21);
}

}  // namespace
}  // namespace mirage::velodyne
