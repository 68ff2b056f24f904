// SPDX-License-Identifier: Apache-2.0
#include "mirage/las/las_reader.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "las_test_points.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_writer.hpp"
#include "test_paths.hpp"

namespace mirage::las {
namespace {

using test::TempDir;

// A valid file of 100 points to corrupt.
std::vector<std::uint8_t> valid_file(const TempDir& dir, std::uint8_t format) {
    const std::string path = dir.file("valid.las");
    {
        LasWriter w(path, core::Georef(), {.point_format = format});
        w.write(test::make_points(100, 21));
    }
    return test::file_bytes(path);
}

// Problems reported for `bytes`, after checking none of them is hidden behind a throw.
std::vector<std::string> problems_of(const TempDir& dir, const std::vector<std::uint8_t>& bytes) {
    const std::string path = dir.file("corrupt.las");
    test::write_bytes(path, bytes);
    return LasFile::read(path).validate();
}

bool any_contains(const std::vector<std::string>& v, const std::string& s) {
    for (const auto& p : v) {
        if (p.find(s) != std::string::npos) return true;
    }
    return false;
}

void put_u64(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

TEST(LasReader, valid_file_has_no_problems) {
    TempDir dir;
    const auto bytes = valid_file(dir, 6);
    EXPECT_EQ(bytes.size(), 375u + 100u * 30u);
    EXPECT_TRUE(problems_of(dir, bytes).empty());
}

// The in-memory entry point (fuzz_las) decodes the bytes exactly as read() decodes the file.
TEST(LasReader, from_bytes_reads_like_the_file) {
    TempDir dir;
    auto bytes = valid_file(dir, 7);
    bytes.resize(bytes.size() - 40);
    const LasFile mem = LasFile::from_bytes(bytes);
    test::write_bytes(dir.file("cut.las"), bytes);
    const LasFile file = LasFile::read(dir.file("cut.las"));
    EXPECT_EQ(mem.file_size(), bytes.size());
    EXPECT_EQ(mem.records_in_file(), 98u);
    ASSERT_EQ(mem.points().size(), file.points().size());
    EXPECT_EQ(mem.points()[97].raw_x, file.points()[97].raw_x);
    EXPECT_EQ(mem.validate(), file.validate());
}

TEST(LasReader, truncated_file_reports_missing_records_and_the_cut_one) {
    TempDir dir;
    auto bytes = valid_file(dir, 6);
    bytes.resize(bytes.size() - 10);
    const auto p = problems_of(dir, bytes);
    EXPECT_TRUE(any_contains(p, "header says 100 points but the file holds only 99 whole records"))
        << ::testing::PrintToString(p);
    EXPECT_TRUE(any_contains(p, "20 bytes after the last whole record"))
        << ::testing::PrintToString(p);
    const LasFile f = LasFile::read(dir.file("corrupt.las"));
    EXPECT_EQ(f.points().size(), 99u);  // only whole records are decoded
}

TEST(LasReader, wrong_point_count_is_reported_with_both_numbers) {
    TempDir dir;
    auto bytes = valid_file(dir, 6);
    put_u64(bytes, 247, 150);
    auto p = problems_of(dir, bytes);
    EXPECT_TRUE(any_contains(p, "header says 150 points but the file holds only 100 whole"))
        << ::testing::PrintToString(p);
    EXPECT_TRUE(any_contains(p, "counts by return sum to 100, point count is 150"))
        << ::testing::PrintToString(p);

    put_u64(bytes, 247, 60);
    p = problems_of(dir, bytes);
    EXPECT_TRUE(any_contains(p, "file holds 100 whole records but the header says 60 points"))
        << ::testing::PrintToString(p);
}

TEST(LasReader, bad_signature_is_reported) {
    TempDir dir;
    auto bytes = valid_file(dir, 6);
    std::memcpy(bytes.data(), "LAZ\x01", 4);
    const auto p = problems_of(dir, bytes);
    EXPECT_TRUE(any_contains(p, "bad signature 'LAZ\\x01' (expected 'LASF')"))
        << ::testing::PrintToString(p);
}

TEST(LasReader, each_header_inconsistency_gets_its_own_message) {
    TempDir dir;
    const auto good = valid_file(dir, 3);
    struct Case {
        const char* what;
        std::size_t at;
        std::vector<std::uint8_t> patch;
        const char* expect;
    };
    const std::vector<Case> cases = {
        {"version", 25, {7}, "unsupported version 1.7"},
        {"header size", 94, {0x10, 0x00}, "header size 16 too small for LAS 1.4 (expected 375)"},
        {"offset", 96, {0xFF, 0xFF, 0xFF, 0x00}, "offset to points 16777215 beyond file size"},
        {"record length", 105, {20, 0}, "record length 20 too short for point format 3 (needs 34)"},
        {"record length", 105, {40, 0}, "record length 40 does not match point format 3"},
        {"legacy count", 107, {99, 0, 0, 0}, "legacy point count 99 differs from point count 100"},
        {"scale", 131, {0, 0, 0, 0, 0, 0, 0, 0}, "scale x is 0, must be > 0"},
        {"max x", 179 + 6, {0x50}, "max x in header is"},
        {"wkt bit", 6, {0x11}, "global encoding WKT bit set but no WKT VLR"},
        {"by return", 255, {1, 0, 0, 0, 0, 0, 0, 0}, "counts by return sum to"},
        {"format", 104, {11}, "point format 11 does not exist"},
    };
    for (const Case& c : cases) {
        auto bytes = good;
        std::copy(c.patch.begin(), c.patch.end(), bytes.begin() + static_cast<long>(c.at));
        const auto p = problems_of(dir, bytes);
        EXPECT_TRUE(any_contains(p, c.expect)) << c.what << ": " << ::testing::PrintToString(p);
    }
}

TEST(LasReader, format_6_with_legacy_fields_or_without_wkt_bit_is_reported) {
    TempDir dir;
    auto bytes = valid_file(dir, 6);
    bytes[107] = 100;  // legacy count must stay 0 for format 6
    bytes[6] = 0x01;   // WKT bit cleared
    const auto p = problems_of(dir, bytes);
    EXPECT_TRUE(any_contains(p, "legacy point count must be 0 for point format 6, is 100"))
        << ::testing::PrintToString(p);
    EXPECT_TRUE(any_contains(p, "point format 6 requires the global encoding WKT bit"))
        << ::testing::PrintToString(p);
}

TEST(LasReader, tiny_and_garbage_files_never_read_out_of_bounds) {
    TempDir dir;
    EXPECT_TRUE(any_contains(problems_of(dir, {'L', 'A'}), "bad signature 'LA'"));
    // Empty: no data() pointer to copy the signature from (UBSan under make asan, fuzz_las).
    EXPECT_TRUE(any_contains(LasFile::from_bytes({}).validate(), "bad signature ''"));
    EXPECT_TRUE(any_contains(problems_of(dir, std::vector<std::uint8_t>(100, 0)),
                             "shorter than the smallest LAS header"));
    // Random header bytes on a valid file: reading must stay in bounds (ASan job) and decode
    // no more records than the file holds.
    const auto good = valid_file(dir, 7);
    std::mt19937 rng(99);
    for (int trial = 0; trial < 300; ++trial) {
        auto bytes = good;
        for (int k = 0; k < 6; ++k) {
            bytes[rng() % 375] = static_cast<std::uint8_t>(rng());
        }
        if (trial % 3 == 0) bytes.resize(rng() % bytes.size());
        const std::string path = dir.file("fuzz.las");
        test::write_bytes(path, bytes);
        const LasFile f = LasFile::read(path);
        EXPECT_LE(f.points().size(), f.records_in_file());
        EXPECT_LE(f.points().size() * 20u, bytes.size());  // 20 B: smallest record
    }
}

TEST(LasReader, unreadable_path_throws_io_error_naming_it) {
    try {
        LasFile::read("/nonexistent-mirage-folder/a.las");
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-mirage-folder/a.las"),
                  std::string::npos);
    }
}

}  // namespace
}  // namespace mirage::las
