// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace mirage::test {

// Third-party captures live outside the project (../shared/captures); a test that needs one
// calls this and skips with a visible message when the folder or file is absent.
inline std::filesystem::path capture_or_skip(const std::string& name) {
    const char* env = std::getenv("MIRAGE_CAPTURES_DIR");
    std::filesystem::path dir = env ? env : MIRAGE_CAPTURES_DIR;
    return dir / name;
}

// CI sets MIRAGE_REQUIRE_CAPTURES=1 where the third-party folders exist (.ci/run): a missing file
// then fails the test instead of skipping it, so a wrong path cannot pass as a skip.
inline bool captures_required() {
    const char* v = std::getenv("MIRAGE_REQUIRE_CAPTURES");
    return v && std::string(v) == "1";
}

// In a test body: `MIRAGE_CAPTURE_OR_SKIP(path, "vlp16_example.pcap");` declares `path` or skips
// the test with a message naming the missing file (GTEST_SKIP must run in the test body itself).
#define MIRAGE_CAPTURE_OR_SKIP(var, name)                                                    \
    const std::filesystem::path var = ::mirage::test::capture_or_skip(name);                 \
    if (!std::filesystem::exists(var) && ::mirage::test::captures_required())                \
        FAIL() << "capture " << var << " not found and MIRAGE_REQUIRE_CAPTURES=1";           \
    if (!std::filesystem::exists(var))                                                       \
    GTEST_SKIP() << "capture " << var << " not found (set MIRAGE_CAPTURES_DIR or the CMake " \
                 << "option MIRAGE_CAPTURES_DIR to the folder of ../shared/captures)"

// Navigation sample data (../shared/nav-io: rst39.log, DBCs) sits beside the captures folder;
// MIRAGE_NAVIO_DIR overrides it.
inline std::filesystem::path navio_file(const std::string& name) {
    if (const char* env = std::getenv("MIRAGE_NAVIO_DIR")) return std::filesystem::path(env) / name;
    const char* cap = std::getenv("MIRAGE_CAPTURES_DIR");
    std::filesystem::path dir = cap ? cap : MIRAGE_CAPTURES_DIR;
    return dir.parent_path() / "nav-io" / name;
}

// `MIRAGE_NAVIO_OR_SKIP(path, "rst39.log");` declares `path` or skips with a visible message
// (fails under MIRAGE_REQUIRE_CAPTURES=1).
#define MIRAGE_NAVIO_OR_SKIP(var, name)                                                        \
    const std::filesystem::path var = ::mirage::test::navio_file(name);                        \
    if (!std::filesystem::exists(var) && ::mirage::test::captures_required())                  \
        FAIL() << "nav-io file " << var << " not found and MIRAGE_REQUIRE_CAPTURES=1";         \
    if (!std::filesystem::exists(var))                                                         \
    GTEST_SKIP() << "nav-io file " << var << " not found (set MIRAGE_NAVIO_DIR to the folder " \
                 << "of ../shared/nav-io)"

inline std::filesystem::path source_dir() { return MIRAGE_SOURCE_DIR; }

// A fresh temporary folder per test, removed at the end.
class TempDir {
  public:
    TempDir() {
        auto base = std::filesystem::temp_directory_path();
        for (int i = 0;; ++i) {
            path_ = base / ("mirage-test-" + std::to_string(::getpid()) + "-" + std::to_string(i));
            if (std::filesystem::create_directory(path_)) break;
        }
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    const std::filesystem::path& path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

  private:
    std::filesystem::path path_;
};

}  // namespace mirage::test
