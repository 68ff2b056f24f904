// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/candump.hpp"

#include <cerrno>
#include <cinttypes>
#include <cstring>

#include "hex.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"

namespace mirage::navcan {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// `(sec.frac)`; frac has exactly 6 or 9 digits (canplayer rejects float-formatted stamps).
bool parse_timestamp(std::string_view tok, std::int64_t& ns) {
    if (tok.size() < 4 || tok.front() != '(' || tok.back() != ')') return false;
    tok = tok.substr(1, tok.size() - 2);
    const std::size_t dot = tok.find('.');
    if (dot == std::string_view::npos || dot == 0 || dot > 10) return false;
    const std::string_view sec = tok.substr(0, dot), frac = tok.substr(dot + 1);
    if (frac.size() != 6 && frac.size() != 9) return false;
    std::int64_t s = 0, f = 0;
    for (char c : sec) {
        if (!is_digit(c)) return false;
        s = s * 10 + (c - '0');
    }
    for (char c : frac) {
        if (!is_digit(c)) return false;
        f = f * 10 + (c - '0');
    }
    if (s > 9'223'372'035) return false;  // int64 ns overflow
    ns = s * core::kNsPerSecond + (frac.size() == 6 ? f * 1000 : f);
    return true;
}

bool parse_dlc_suffix(std::string_view rest, std::uint8_t& raw_dlc) {
    if (rest.size() != 2 || rest[0] != '_') return false;
    const int v = detail::hex_value(rest[1]);
    if (v < 9) return false;  // only DLC 9..F say more than len 8
    raw_dlc = static_cast<std::uint8_t>(v);
    return true;
}

CandumpStatus parse_frame(std::string_view t, nav::CanFrame& f, std::uint8_t& raw_dlc) {
    f = nav::CanFrame{};
    raw_dlc = 0;
    const std::size_t hash = t.find('#');
    if (hash != 3 && hash != 8) return CandumpStatus::BadFrame;
    std::uint32_t id = 0;
    if (!detail::parse_hex(t.substr(0, hash), id)) return CandumpStatus::BadFrame;
    if (hash == 3) {
        if (id > 0x7FFu) return CandumpStatus::BadFrame;
    } else if (id & kCanErrFlag) {
        f.error = true;
        id &= 0x1FFF'FFFFu;
    } else {
        if (id > 0x1FFF'FFFFu) return CandumpStatus::BadFrame;
        f.extended = true;
    }
    f.id = id;
    std::string_view rest = t.substr(hash + 1);
    if (!rest.empty() && rest[0] == '#') return CandumpStatus::CanFd;
    if (!rest.empty() && (rest[0] == 'R' || rest[0] == 'r') && !f.error) {
        f.rtr = true;
        rest.remove_prefix(1);
        if (!rest.empty() && rest[0] != '_') {
            if (rest[0] < '0' || rest[0] > '8') return CandumpStatus::BadFrame;
            f.len = static_cast<std::uint8_t>(rest[0] - '0');
            rest.remove_prefix(1);
        }
        if (rest.empty()) return CandumpStatus::Ok;
        if (f.len == 8 && parse_dlc_suffix(rest, raw_dlc)) return CandumpStatus::Ok;
        return CandumpStatus::BadFrame;
    }
    std::size_t i = 0;
    while (i < rest.size()) {
        if (rest[i] == '.') {
            ++i;
            continue;
        }
        if (rest[i] == '_') {
            if (f.len == 8 && parse_dlc_suffix(rest.substr(i), raw_dlc)) return CandumpStatus::Ok;
            return CandumpStatus::BadFrame;
        }
        if (f.len >= 8 || i + 1 >= rest.size()) return CandumpStatus::BadFrame;
        const int hi = detail::hex_value(rest[i]), lo = detail::hex_value(rest[i + 1]);
        if (hi < 0 || lo < 0) return CandumpStatus::BadFrame;
        f.data[f.len++] = static_cast<std::uint8_t>(hi * 16 + lo);
        i += 2;
    }
    return CandumpStatus::Ok;
}

std::string_view next_token(std::string_view& s) {
    std::size_t i = 0;
    while (i < s.size() && is_space(s[i])) ++i;
    std::size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    const std::string_view tok = s.substr(i, j - i);
    s.remove_prefix(j);
    return tok;
}

}  // namespace

const char* to_string(CandumpStatus s) {
    switch (s) {
        case CandumpStatus::Ok:
            return "ok";
        case CandumpStatus::Blank:
            return "blank";
        case CandumpStatus::BadTimestamp:
            return "bad timestamp";
        case CandumpStatus::BadInterface:
            return "bad interface";
        case CandumpStatus::BadFrame:
            return "bad frame";
        case CandumpStatus::CanFd:
            return "CAN FD not supported";
    }
    return "?";
}

CandumpStatus parse_candump_line(std::string_view line, CandumpRecord& out) {
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.remove_suffix(1);
    std::string_view rest = line;
    const std::string_view ts = next_token(rest);
    if (ts.empty() || ts[0] == '#') return CandumpStatus::Blank;
    std::int64_t ns = 0;
    if (!parse_timestamp(ts, ns)) return CandumpStatus::BadTimestamp;
    const std::string_view iface = next_token(rest);
    if (iface.empty() || iface.size() > kCandumpMaxIfname) return CandumpStatus::BadInterface;
    const std::string_view frame = next_token(rest);
    if (frame.empty()) return CandumpStatus::BadFrame;
    const std::string_view dir = next_token(rest);
    if (!(dir.empty() || dir == "R" || dir == "T") || !next_token(rest).empty()) {
        return CandumpStatus::BadFrame;
    }
    nav::CanFrame f;
    std::uint8_t raw_dlc = 0;
    const CandumpStatus st = parse_frame(frame, f, raw_dlc);
    if (st != CandumpStatus::Ok) return st;
    out.stamped.time_ns = ns;
    out.stamped.frame = f;
    out.interface.assign(iface);
    out.raw_dlc = raw_dlc;
    out.direction = dir.empty() ? '\0' : dir[0];
    return CandumpStatus::Ok;
}

std::string format_candump_line(const CandumpRecord& rec, bool nanoseconds) {
    const std::int64_t ns = rec.stamped.time_ns < 0 ? 0 : rec.stamped.time_ns;
    char stamp[48];
    if (nanoseconds) {
        std::snprintf(stamp, sizeof stamp, "(%010" PRId64 ".%09" PRId64 ") ",
                      ns / core::kNsPerSecond, ns % core::kNsPerSecond);
    } else {
        std::snprintf(stamp, sizeof stamp, "(%010" PRId64 ".%06" PRId64 ") ",
                      ns / core::kNsPerSecond, (ns % core::kNsPerSecond) / 1000);
    }
    const nav::CanFrame& f = rec.stamped.frame;
    std::string s = stamp;
    s.append(rec.interface);
    s.push_back(' ');
    if (f.error) {
        detail::append_hex(s, (f.id & 0x1FFF'FFFFu) | kCanErrFlag, 8);
    } else if (f.extended) {
        detail::append_hex(s, f.id & 0x1FFF'FFFFu, 8);
    } else {
        detail::append_hex(s, f.id & 0x7FFu, 3);
    }
    s.push_back('#');
    const std::uint8_t len = f.len > 8 ? std::uint8_t{8} : f.len;
    if (f.rtr && !f.error) {
        s.push_back('R');
        if (len > 0) s.push_back(static_cast<char>('0' + len));
    } else {
        for (std::size_t i = 0; i < len; ++i) detail::append_hex(s, f.data[i], 2);
    }
    if (len == 8 && rec.raw_dlc >= 9 && rec.raw_dlc <= 15) {
        s.push_back('_');
        s.push_back(detail::kHexUpper[rec.raw_dlc]);
    }
    if (rec.direction == 'R' || rec.direction == 'T') {
        s.push_back(' ');
        s.push_back(rec.direction);
    }
    return s;
}

std::string format_candump_line(std::int64_t unix_ns, std::string_view interface,
                                const nav::CanFrame& frame) {
    CandumpRecord rec;
    rec.stamped = {unix_ns, frame};
    rec.interface.assign(interface);
    return format_candump_line(rec);
}

CandumpReader::CandumpReader(const std::filesystem::path& path) {
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) {
        throw IoError("candump '" + path.string() + "': cannot open: " + std::strerror(errno));
    }
}

CandumpReader::~CandumpReader() {
    if (file_) std::fclose(file_);
}

bool CandumpReader::next(CandumpRecord& out) {
    for (;;) {
        line_.clear();
        int c = 0;
        while ((c = std::fgetc(file_)) != EOF && c != '\n') {
            // A line far longer than any frame is rejected without growing without bound.
            if (line_.size() < 512) line_.push_back(static_cast<char>(c));
        }
        if (c == EOF && line_.empty()) return false;
        ++stats_.lines;
        const CandumpStatus st =
            line_.size() >= 512 ? CandumpStatus::BadFrame : parse_candump_line(line_, out);
        switch (st) {
            case CandumpStatus::Ok:
                ++stats_.records;
                return true;
            case CandumpStatus::Blank:
                ++stats_.blank;
                continue;
            case CandumpStatus::BadTimestamp:
                ++stats_.bad_timestamp;
                break;
            case CandumpStatus::BadInterface:
                ++stats_.bad_interface;
                break;
            case CandumpStatus::BadFrame:
                ++stats_.bad_frame;
                break;
            case CandumpStatus::CanFd:
                ++stats_.can_fd;
                break;
        }
        if (stats_.first_bad_line == 0) stats_.first_bad_line = stats_.lines;
    }
}

CandumpWriter::CandumpWriter(const std::filesystem::path& path, bool nanoseconds)
    : path_(path.string()), nanoseconds_(nanoseconds) {
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) {
        throw IoError("candump '" + path_ + "': cannot create: " + std::strerror(errno));
    }
}

CandumpWriter::~CandumpWriter() {
    if (file_) std::fclose(file_);
}

bool CandumpWriter::write(const CandumpRecord& rec) {
    if (!file_ || !ok_) return false;
    std::string line = format_candump_line(rec, nanoseconds_);
    line.push_back('\n');
    if (std::fwrite(line.data(), 1, line.size(), file_) != line.size()) ok_ = false;
    return ok_;
}

bool CandumpWriter::write(std::int64_t unix_ns, std::string_view interface,
                          const nav::CanFrame& frame) {
    CandumpRecord rec;
    rec.stamped = {unix_ns, frame};
    rec.interface.assign(interface);
    return write(rec);
}

bool CandumpWriter::close() {
    if (!file_) return ok_;
    if (std::fclose(file_) != 0) ok_ = false;
    file_ = nullptr;
    return ok_;
}

}  // namespace mirage::navcan
