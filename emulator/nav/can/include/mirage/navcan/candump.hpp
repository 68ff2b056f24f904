// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "mirage/nav/can_frame.hpp"

// candump -L log lines (docs/nav-protocols.md §8; can-utils lib.h parse_canframe / canplayer):
// `(<sec>.<usec>) <iface> <frame>`, e.g. `(1700000000.000000) vcan0 601#081EAE1C184FDD06`.
// Timestamps are Unix time; exactly 6 (µs) or 9 (ns) fractional digits, as canplayer demands.
// Frames: 3 hex digits = 11-bit ID, 8 = 29-bit ID; 8 digits with CAN_ERR_FLAG (0x20000000) =
// error frame (id = the CAN_ERR_* class bits, len 8); `#R` / `#R<len>` RTR; data bytes may be
// separated by `.`; `_<dlc>` after 8 bytes gives a raw DLC 9..F. CAN FD (`##`) is rejected.
// Newer can-utils (asc2log, candump -x) may append a direction token ` R` / ` T`: accepted.
namespace mirage::navcan {

inline constexpr std::uint32_t kCanErrFlag = 0x2000'0000u;
inline constexpr std::size_t kCandumpMaxIfname = 21;

enum class CandumpStatus : std::uint8_t {
    Ok,
    Blank,         // empty or whitespace-only line (or a `#` comment): not an error
    BadTimestamp,  // missing parentheses, not digits, or not 6/9 fractional digits
    BadInterface,  // missing or longer than kCandumpMaxIfname
    BadFrame,      // malformed frame text, ID too wide, > 8 bytes, bad DLC suffix, extra text
    CanFd,         // `##` CAN FD frame: valid syntax, not supported (classic CAN only)
};
const char* to_string(CandumpStatus s);

struct CandumpRecord {
    nav::StampedCanFrame stamped;  // time_ns = Unix ns
    std::string interface;
    std::uint8_t raw_dlc = 0;  // 9..15 when the line had `_<dlc>` (len stays 8), else 0
    char direction = 0;        // 'R' / 'T' when the line ended in a direction token
};

// Parses one line (a trailing `\n`/`\r\n` is ignored). Never throws.
CandumpStatus parse_candump_line(std::string_view line, CandumpRecord& out);

// `(sec.usec) iface frame` without a newline. Upper-case hex like candump; the time is written
// with 6 digits (truncated to µs) unless `nanoseconds`. Negative times clamp to 0.
std::string format_candump_line(const CandumpRecord& rec, bool nanoseconds = false);
std::string format_candump_line(std::int64_t unix_ns, std::string_view interface,
                                const nav::CanFrame& frame);

struct CandumpReadStats {
    std::uint64_t lines = 0;
    std::uint64_t records = 0;
    std::uint64_t blank = 0;
    std::uint64_t bad_timestamp = 0;
    std::uint64_t bad_interface = 0;
    std::uint64_t bad_frame = 0;
    std::uint64_t can_fd = 0;
    std::uint64_t first_bad_line = 0;  // 1-based line number of the first rejected line, 0 none
    std::uint64_t rejected() const { return bad_timestamp + bad_interface + bad_frame + can_fd; }
};

// Reads a candump log line by line; bad lines are skipped and counted, never thrown.
// Constructor throws mirage::IoError ("candump 'f.log': cannot open ...").
class CandumpReader {
  public:
    explicit CandumpReader(const std::filesystem::path& path);
    ~CandumpReader();
    CandumpReader(const CandumpReader&) = delete;
    CandumpReader& operator=(const CandumpReader&) = delete;

    // Next valid record; false at end of file.
    bool next(CandumpRecord& out);
    const CandumpReadStats& stats() const { return stats_; }

  private:
    std::FILE* file_ = nullptr;
    std::string line_;
    CandumpReadStats stats_;
};

// Writes candump -L lines. Constructor throws IoError; write() returns false (and stays false
// from then on, see ok()) on a write error instead of throwing.
class CandumpWriter {
  public:
    explicit CandumpWriter(const std::filesystem::path& path, bool nanoseconds = false);
    ~CandumpWriter();
    CandumpWriter(const CandumpWriter&) = delete;
    CandumpWriter& operator=(const CandumpWriter&) = delete;

    bool write(const CandumpRecord& rec);
    bool write(std::int64_t unix_ns, std::string_view interface, const nav::CanFrame& frame);
    // Flushes and closes; false if any write failed. The destructor closes silently.
    bool close();
    bool ok() const { return ok_; }

  private:
    std::FILE* file_ = nullptr;
    std::string path_;
    bool nanoseconds_ = false;
    bool ok_ = true;
};

}  // namespace mirage::navcan
