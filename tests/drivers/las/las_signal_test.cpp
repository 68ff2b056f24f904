// SPDX-License-Identifier: Apache-2.0
// Files stay valid when the process dies by SIGINT/SIGTERM or the disk fills up. Each case runs
// the writer in a fork()ed child and inspects the file from the parent.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <string>

#include "las_test_points.hpp"
#include "mirage/core/error.hpp"
#include "mirage/las/las_reader.hpp"
#include "mirage/las/las_writer.hpp"
#include "test_paths.hpp"

namespace mirage::las {
namespace {

using test::TempDir;

int wait_for(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
}

std::string read_all(int fd) {
    std::string out;
    char buf[512];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
}

void expect_points_match(const LasFile& f, const std::vector<core::PointRecord>& pts) {
    for (std::size_t k = 0; k < f.points().size(); ++k) {
        const core::PointRecord& e = pts[k % pts.size()];
        ASSERT_NEAR(f.points()[k].x, e.x, 0.0005) << k;
        ASSERT_NEAR(f.points()[k].z, e.z, 0.0005) << k;
        ASSERT_EQ(f.points()[k].intensity, e.intensity) << k;
    }
}

TEST(LasSignal, sigint_after_ten_flushes_leaves_the_flushed_records_and_a_matching_header) {
    TempDir dir;
    const std::string path = dir.file("sigint.las");
    const auto pts = test::make_points(1050, 31);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        install_signal_finalizer();
        try {
            // 100 records per buffer: 10 flushes after 1000 points, 50 still buffered.
            LasWriter w(path, core::Georef(), {.point_format = 6, .buffer_bytes = 3000});
            for (std::size_t k = 0; k < pts.size(); k += 50) w.write(std::span(pts).subspan(k, 50));
            if (w.points_flushed() != 1000) ::_exit(4);
            std::raise(SIGINT);
        } catch (...) {
            ::_exit(2);
        }
        ::_exit(3);  // not reached: SIGINT terminates
    }
    const int status = wait_for(pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().point_count, 1000u);
    EXPECT_EQ(f.records_in_file(), 1000u);
    EXPECT_EQ(f.file_size(), 375u + 1000u * 30u);
    expect_points_match(f, pts);
}

TEST(LasSignal, sigterm_at_an_arbitrary_moment_leaves_a_valid_file) {
    TempDir dir;
    const std::string path = dir.file("sigterm.las");
    const auto pts = test::make_points(1000, 32);
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(ready[0]);
        install_signal_finalizer();
        try {
            LasWriter w(path, core::Georef(), {.point_format = 7, .buffer_bytes = 4096});
            bool told = false;
            // Bounded: at most 500k points (18 MB) before waiting for the signal idle.
            for (int i = 0; i < 500; ++i) {
                w.write(pts);
                if (!told && w.points_flushed() > 0) {
                    told = ::write(ready[1], "r", 1) == 1;
                }
            }
            for (;;) ::pause();
        } catch (...) {
            ::_exit(2);
        }
    }
    ::close(ready[1]);
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    ::close(ready[0]);
    ::kill(pid, SIGTERM);
    const int status = wait_for(pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().point_count, f.records_in_file());
    EXPECT_GE(f.header().point_count, 113u);  // at least one 4096-byte buffer of 36-byte records
    expect_points_match(f, pts);
    std::printf("SIGTERM: %llu points on disk, file %llu bytes\n",
                static_cast<unsigned long long>(f.header().point_count),
                static_cast<unsigned long long>(f.file_size()));
}

struct DiskFullResult {
    int status = 0;
    std::string message;
};

// Runs `body` in a child whose files may not grow beyond `limit` bytes (EFBIG instead of
// SIGXFSZ). The child writes the IoError message to a pipe.
template <class Body>
DiskFullResult run_with_file_size_limit(rlim_t limit, Body body) {
    int msg[2];
    if (::pipe(msg) != 0) return {-1, "pipe failed"};
    const pid_t pid = ::fork();
    if (pid < 0) return {-1, "fork failed"};
    if (pid == 0) {
        ::close(msg[0]);
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit rl{limit, limit};
        if (::setrlimit(RLIMIT_FSIZE, &rl) != 0) ::_exit(5);
        int code = 1;  // no IoError
        try {
            body();
        } catch (const IoError& e) {
            const std::string what = e.what();
            code = ::write(msg[1], what.data(), what.size()) == static_cast<ssize_t>(what.size())
                       ? 0
                       : 6;
        } catch (...) {
            code = 2;
        }
        ::_exit(code);
    }
    ::close(msg[1]);
    DiskFullResult r;
    r.message = read_all(msg[0]);
    ::close(msg[0]);
    r.status = wait_for(pid);
    return r;
}

TEST(LasDiskFull, efbig_on_close_cuts_the_file_to_whole_records_and_names_it) {
    TempDir dir;
    const std::string path = dir.file("full.las");
    const auto pts = test::make_points(10000, 41);
    // Default 1 MiB buffer: everything is written at close(); 99 625 bytes fit after the
    // header, i.e. 2930 whole 34-byte records and 5 bytes of a cut one.
    const auto r = run_with_file_size_limit(100000, [&] {
        LasWriter w(path, core::Georef(), {.point_format = 3});
        w.write(pts);
        w.close();
    });
    ASSERT_TRUE(WIFEXITED(r.status));
    ASSERT_EQ(WEXITSTATUS(r.status), 0) << r.message;
    EXPECT_EQ(r.message, "las writer '" + path + "': " + std::strerror(EFBIG) +
                             " after 2930 points; file cut to 2930 whole records");
    const LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().point_count, 2930u);
    EXPECT_EQ(f.header().legacy_point_count, 2930u);
    EXPECT_EQ(f.file_size(), 375u + 2930u * 34u);
    expect_points_match(f, pts);
    std::printf("EFBIG at close: limit 100000 B -> %llu points, %llu bytes: %s\n",
                static_cast<unsigned long long>(f.header().point_count),
                static_cast<unsigned long long>(f.file_size()), r.message.c_str());
}

// A format-7 file cut by a 50 000-byte limit after 1378 whole records: message, header, size and
// the records themselves.
LasFile expect_cut_after_1378(const DiskFullResult& r, const std::string& path,
                              const std::vector<core::PointRecord>& pts) {
    EXPECT_TRUE(WIFEXITED(r.status));
    EXPECT_EQ(WEXITSTATUS(r.status), 0) << r.message;
    EXPECT_NE(r.message.find("after 1378 points; file cut to 1378 whole records"),
              std::string::npos)
        << r.message;
    LasFile f = LasFile::read(path);
    EXPECT_TRUE(f.validate().empty()) << ::testing::PrintToString(f.validate());
    EXPECT_EQ(f.header().point_count, 1378u);
    EXPECT_EQ(f.file_size(), 375u + 1378u * 36u);
    expect_points_match(f, pts);
    return f;
}

TEST(LasDiskFull, efbig_mid_stream_keeps_earlier_flushes_and_the_whole_part_of_the_last) {
    TempDir dir;
    const std::string path = dir.file("full7.las");
    const auto pts = test::make_points(5000, 42);
    // 100 records of 36 B per flush: 13 flushes fit (1300 records, 47 175 B), the 14th is cut
    // at 50 000 B: 78 more whole records.
    const auto r = run_with_file_size_limit(50000, [&] {
        LasWriter w(path, core::Georef(), {.point_format = 7, .buffer_bytes = 3600});
        for (std::size_t k = 0; k < pts.size(); k += 10) w.write(std::span(pts).subspan(k, 10));
        w.close();
    });
    const LasFile f = expect_cut_after_1378(r, path, pts);
    std::printf("EFBIG mid-stream: limit 50000 B -> %llu points, %llu bytes\n",
                static_cast<unsigned long long>(f.header().point_count),
                static_cast<unsigned long long>(f.file_size()));
}

// The same disk limit when the records arrive encoded (write_encoded, as from the render
// workers): chunks of 100 records; 13 fit, the 14th is cut after 78 whole records.
TEST(LasDiskFull, efbig_in_an_encoded_chunk_keeps_the_whole_records_before_it) {
    TempDir dir;
    const std::string path = dir.file("full_encoded.las");
    const auto pts = test::make_points(5000, 42);
    const auto r = run_with_file_size_limit(50000, [&] {
        LasWriter w(path, core::Georef(), {.point_format = 7});
        EncodedRecords chunk;
        for (std::size_t k = 0; k < pts.size(); k += 100) {
            chunk.clear();
            w.encode(std::span(pts).subspan(k, 100), chunk);
            w.write_encoded(chunk);
        }
        w.close();
    });
    expect_cut_after_1378(r, path, pts);
}

}  // namespace
}  // namespace mirage::las
