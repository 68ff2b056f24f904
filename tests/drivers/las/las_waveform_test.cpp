// SPDX-License-Identifier: Apache-2.0
// Full-waveform LAS (formats 4, 5, 9, 10; docs/file-formats.md §6.1): packets written once per
// pulse and read back sample for sample, in the EVLR or a .wdp file, with the echo fields; the
// reader's checks catch a packet that points outside its record.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "las_test_points.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_reader.hpp"
#include "mirage/las/las_writer.hpp"
#include "test_paths.hpp"

namespace mirage::las {
namespace {

using test::TempDir;

constexpr std::uint32_t kSamples = 40;

// Pulses of 1–3 returns sharing one window each; every fifth pulse records none.
struct Pulses {
    std::vector<core::PointRecord> points;
    std::vector<std::uint32_t> samples;
};

Pulses make_pulses(std::size_t n, std::uint32_t max_value) {
    Pulses out;
    auto pts = test::make_points(3 * n, 5u, 7, 31);
    std::size_t used = 0;
    for (std::size_t pulse = 0; pulse < n; ++pulse) {
        const bool recorded = pulse % 5 != 4;
        const std::uint32_t wave = static_cast<std::uint32_t>(out.samples.size());
        if (recorded)
            for (std::uint32_t k = 0; k < kSamples; ++k)
                out.samples.push_back(
                    static_cast<std::uint32_t>((pulse * 7919 + k * 104729) % (max_value + 1)));
        const std::size_t returns = 1 + pulse % 3;
        for (std::size_t r = 0; r < returns; ++r) {
            core::PointRecord p = pts[used++];
            p.return_number = static_cast<std::uint8_t>(r + 1);
            p.number_of_returns = static_cast<std::uint8_t>(returns);
            p.wave = recorded ? wave : core::PointRecord::kNoWave;
            p.wave_location_ps = static_cast<float>(1000 * (3 + 10 * r));
            p.beam_dz = -1.0f;
            p.amplitude = static_cast<float>(pulse);
            p.echo_width_ns = 1.5f;
            p.deviation = 0.25f * static_cast<float>(r);
            out.points.push_back(p);
        }
    }
    return out;
}

struct Case {
    int format;
    int bits;
    bool external;
};

class LasWaveform : public ::testing::TestWithParam<Case> {};

TEST_P(LasWaveform, packets_and_echo_fields_survive_write_and_read) {
    const Case c = GetParam();
    TempDir dir;
    const std::string path = dir.file("w.las");
    const Pulses in = make_pulses(300, c.bits == 8 ? 300u : 70000u);  // 8 bits: some saturate
    LasWriterOptions o;
    o.point_format = static_cast<std::uint8_t>(c.format);
    o.waveform = {static_cast<std::uint8_t>(c.bits), kSamples, 1000, 0.25, -25.0, c.external};
    o.echo_fields = true;
    {
        LasWriter w(path, core::Georef(), o);
        const std::size_t half = 301;  // a pulse's returns split over two calls
        w.write_recorded(std::span(in.points).first(half), in.samples);
        w.write_recorded(std::span(in.points).subspan(half), in.samples);
        w.close();
    }
    EXPECT_EQ(std::filesystem::exists(dir.file("w.wdp")), c.external);
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().global_encoding & 6, c.external ? 4 : 2);
    ASSERT_EQ(f.points().size(), in.points.size());
    const std::uint32_t top = c.bits == 8 ? 255u : c.bits == 16 ? 65535u : 0xFFFFFFFFu;
    std::size_t packets = 0;
    std::uint64_t last = 0;
    for (std::size_t k = 0; k < in.points.size(); ++k) {
        const core::PointRecord& e = in.points[k];
        const LasPoint& p = f.points()[k];
        ASSERT_EQ(p.amplitude, e.amplitude);
        ASSERT_EQ(p.deviation, e.deviation);
        if (e.wave == core::PointRecord::kNoWave) {
            ASSERT_EQ(p.wave_index, 0) << k;
            continue;
        }
        ASSERT_EQ(p.wave_index, 1) << k;
        ASSERT_EQ(p.wave_location_ps, e.wave_location_ps);
        ASSERT_NEAR(p.wave_dz, 0.5 * 299792458.0e-12, 1e-9);  // back up the beam, c/2 per ps
        packets += p.wave_offset != last;
        last = p.wave_offset;
        const auto s = f.waveform(p);
        ASSERT_EQ(s.size(), kSamples);
        for (std::uint32_t j = 0; j < kSamples; ++j)
            ASSERT_EQ(s[j], std::min(in.samples[e.wave + j], top)) << k << " " << j;
    }
    EXPECT_EQ(packets, 240u);  // one per recorded pulse, not per return
}

INSTANTIATE_TEST_SUITE_P(Formats, LasWaveform,
                         ::testing::Values(Case{4, 8, false}, Case{5, 16, true}, Case{9, 16, false},
                                           Case{10, 32, true}, Case{9, 16, true}));

// 20 pulses in `format`, packets in the EVLR or the .wdp.
void write_small(const std::string& path, std::uint8_t format, bool external) {
    const Pulses in = make_pulses(20, 4095);
    LasWriterOptions o;
    o.point_format = format;
    o.waveform.samples = kSamples;
    o.waveform.external = external;
    LasWriter w(path, core::Georef(), o);
    w.write_recorded(in.points, in.samples);
}

TEST(LasWaveform, reader_flags_a_packet_outside_the_record) {
    TempDir dir;
    const std::string path = dir.file("w.las");
    write_small(path, 9, false);
    ASSERT_TRUE(LasFile::read(path).validate().empty());
    // Point 3's offset (format 9: wave fields at byte 30, offset after the index byte).
    std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
    const auto h = LasFile::read(path).header();
    io.seekp(static_cast<std::streamoff>(h.offset_to_points + 3 * h.record_length + 31));
    const std::uint64_t far = 1u << 30;
    io.write(reinterpret_cast<const char*>(&far), 8);
    io.close();
    const auto problems = LasFile::read(path).validate();
    ASSERT_EQ(problems.size(), 1u) << ::testing::PrintToString(problems);
    EXPECT_NE(problems[0].find("point 3: packet at 1073741824"), std::string::npos) << problems[0];
}

TEST(LasWaveform, external_packets_missing_are_a_problem) {
    TempDir dir;
    const std::string path = dir.file("w.las");
    write_small(path, 4, true);
    std::filesystem::remove(dir.file("w.wdp"));
    const auto problems = LasFile::read(path).validate();
    ASSERT_FALSE(problems.empty());
    EXPECT_NE(problems.back().find("cannot be read"), std::string::npos) << problems.back();
}

TEST(LasWaveform, bad_descriptors_are_config_errors) {
    TempDir dir;
    LasWriterOptions o;
    o.point_format = 9;
    o.waveform.samples = 0;
    EXPECT_THROW(LasWriter(dir.file("a.las"), core::Georef(), o), ConfigError);
    o.waveform.samples = 10;
    o.waveform.bits = 12;
    EXPECT_THROW(LasWriter(dir.file("b.las"), core::Georef(), o), ConfigError);
    o.point_format = 8;
    o.waveform.bits = 16;
    EXPECT_THROW(LasWriter(dir.file("c.las"), core::Georef(), o), ConfigError);
}

}  // namespace
}  // namespace mirage::las
