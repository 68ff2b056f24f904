// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/slcan.hpp"

#include <array>

#include "hex.hpp"

namespace mirage::navcan {
namespace {

constexpr std::array<std::uint32_t, 9> kBitrates = {10'000,  20'000,  50'000,  100'000,  125'000,
                                                    250'000, 500'000, 800'000, 1'000'000};
constexpr std::uint32_t kTimestampWrap = 60'000;  // Z timestamps count ms within a minute

bool parse_frame(std::string_view line, SlcanEvent& out) {
    const char type = line[0];
    const bool extended = type == 'T' || type == 'R';
    const bool rtr = type == 'r' || type == 'R';
    const std::size_t id_digits = extended ? 8 : 3;
    if (line.size() < 1 + id_digits + 1) return false;
    std::uint32_t id = 0;
    if (!detail::parse_hex(line.substr(1, id_digits), id)) return false;
    if (id > (extended ? 0x1FFF'FFFFu : 0x7FFu)) return false;
    const char dlc = line[1 + id_digits];
    if (dlc < '0' || dlc > '8') return false;  // Linux slcan: classic frames only, DLC 0..8
    const auto len = static_cast<std::uint8_t>(dlc - '0');
    const std::size_t data_chars = rtr ? 0 : 2u * len;
    const std::size_t base = 2 + id_digits + data_chars;
    if (line.size() != base && line.size() != base + 4) return false;

    nav::CanFrame f;
    f.id = id;
    f.extended = extended;
    f.rtr = rtr;
    f.len = len;
    for (std::size_t i = 0; i < data_chars / 2; ++i) {
        std::uint32_t b = 0;
        if (!detail::parse_hex(line.substr(2 + id_digits + 2 * i, 2), b)) return false;
        f.data[i] = static_cast<std::uint8_t>(b);
    }
    out = SlcanEvent{};
    out.kind = SlcanEvent::Kind::Frame;
    out.frame = f;
    if (line.size() == base + 4) {
        std::uint32_t ts = 0;
        if (!detail::parse_hex(line.substr(base, 4), ts) || ts >= kTimestampWrap) return false;
        out.timestamp_ms = static_cast<std::uint16_t>(ts);
    }
    return true;
}

bool parse_command(std::string_view line, SlcanEvent& out) {
    using K = SlcanCommand::Kind;
    SlcanCommand c;
    const std::string_view arg = line.substr(1);
    c.text = std::string(arg);
    std::uint32_t v = 0;
    switch (line[0]) {
        case 'S': {
            if (arg.size() != 1 || arg[0] < '0' || arg[0] > '8') return false;
            c.kind = K::SetBitrate;
            c.value = static_cast<std::uint32_t>(arg[0] - '0');
            c.has_value = true;
            c.bitrate_bps = kBitrates[c.value];
            break;
        }
        case 's':
            if (arg.size() != 4 || !detail::parse_hex(arg, v)) return false;
            c.kind = K::SetBtr;
            c.value = v;
            c.has_value = true;
            break;
        case 'O':
        case 'L':
        case 'C':
            if (!arg.empty()) return false;
            c.kind = line[0] == 'O' ? K::Open : line[0] == 'L' ? K::OpenListenOnly : K::Close;
            break;
        case 'F':
            c.kind = K::Status;
            if (arg.empty()) break;
            if (arg.size() != 2 || !detail::parse_hex(arg, v)) return false;
            c.value = v;
            c.has_value = true;
            break;
        case 'V':
        case 'v':
            c.kind = line[0] == 'V' ? K::Version : K::SwVersion;
            if (arg.empty()) break;
            if (arg.size() != 4 || !detail::parse_hex(arg, v)) return false;
            c.value = v;
            c.has_value = true;
            break;
        case 'N':
            c.kind = K::Serial;
            if (arg.empty()) break;
            if (arg.size() != 4) return false;
            for (char ch : arg) {
                if (static_cast<unsigned char>(ch) < 0x21 || static_cast<unsigned char>(ch) > 0x7E)
                    return false;
            }
            c.has_value = true;
            break;
        case 'Z':
        case 'z':
            if (arg.empty()) {
                c.kind = K::TransmitAck;
                break;
            }
            if (line[0] != 'Z' || arg.size() != 1 || (arg[0] != '0' && arg[0] != '1')) return false;
            c.kind = K::Timestamps;
            c.value = static_cast<std::uint32_t>(arg[0] - '0');
            c.has_value = true;
            break;
        default:
            return false;
    }
    out = SlcanEvent{};
    out.kind = SlcanEvent::Kind::Command;
    out.command = std::move(c);
    return true;
}

bool is_frame_letter(char c) { return c == 't' || c == 'T' || c == 'r' || c == 'R'; }

}  // namespace

std::optional<std::uint32_t> slcan_bitrate_bps(int code) {
    if (code < 0 || code > 8) return std::nullopt;
    return kBitrates[static_cast<std::size_t>(code)];
}

std::optional<int> slcan_bitrate_code(std::uint32_t bitrate_bps) {
    for (std::size_t i = 0; i < kBitrates.size(); ++i) {
        if (kBitrates[i] == bitrate_bps) return static_cast<int>(i);
    }
    return std::nullopt;
}

namespace {
std::string encode_body(const nav::CanFrame& f) {
    std::string s;
    if (f.error) return s;
    s.reserve(kSlcanMaxLine + 1);
    const std::uint8_t len = f.len > 8 ? std::uint8_t{8} : f.len;
    if (f.extended) {
        s.push_back(f.rtr ? 'R' : 'T');
        detail::append_hex(s, f.id & 0x1FFF'FFFFu, 8);
    } else {
        s.push_back(f.rtr ? 'r' : 't');
        detail::append_hex(s, f.id & 0x7FFu, 3);
    }
    s.push_back(static_cast<char>('0' + len));
    if (!f.rtr) {
        for (std::size_t i = 0; i < len; ++i) detail::append_hex(s, f.data[i], 2);
    }
    return s;
}
}  // namespace

std::string slcan_encode(const nav::CanFrame& frame) {
    std::string s = encode_body(frame);
    if (!s.empty()) s.push_back(kSlcanOk);
    return s;
}

std::string slcan_encode(const nav::CanFrame& frame, std::uint16_t timestamp_ms) {
    std::string s = encode_body(frame);
    if (s.empty()) return s;
    detail::append_hex(s, timestamp_ms % kTimestampWrap, 4);
    s.push_back(kSlcanOk);
    return s;
}

std::string slcan_command_text(const SlcanCommand& cmd) {
    using K = SlcanCommand::Kind;
    // Built with push_back: g++ 12 reports a false -Wrestrict on short literal assignments.
    std::string s;
    s.reserve(8);
    switch (cmd.kind) {
        case K::SetBitrate: {
            // A bitrate that has a code wins over `value`, so callers may fill either.
            int code = static_cast<int>(cmd.value > 8 ? 8 : cmd.value);
            if (cmd.bitrate_bps != 0) {
                if (auto c = slcan_bitrate_code(cmd.bitrate_bps)) code = *c;
            }
            s.push_back('S');
            s.push_back(static_cast<char>('0' + code));
            break;
        }
        case K::SetBtr:
            s.push_back('s');
            detail::append_hex(s, cmd.value & 0xFFFFu, 4);
            break;
        case K::Open:
            s.push_back('O');
            break;
        case K::OpenListenOnly:
            s.push_back('L');
            break;
        case K::Close:
            s.push_back('C');
            break;
        case K::Status:
            s.push_back('F');
            if (cmd.has_value) detail::append_hex(s, cmd.value & 0xFFu, 2);
            break;
        case K::Version:
        case K::SwVersion:
            s.push_back(cmd.kind == K::Version ? 'V' : 'v');
            if (cmd.has_value) detail::append_hex(s, cmd.value & 0xFFFFu, 4);
            break;
        case K::Serial:
            s.push_back('N');
            if (cmd.has_value) s.append(cmd.text);
            break;
        case K::Timestamps:
            s.push_back('Z');
            s.push_back(cmd.value != 0 ? '1' : '0');
            break;
        case K::TransmitAck:
            s.push_back('z');
            break;
    }
    s.push_back(kSlcanOk);
    return s;
}

std::string slcan_open_sequence(std::uint32_t bitrate_bps, bool listen_only) {
    const auto code = slcan_bitrate_code(bitrate_bps);
    if (!code) return {};
    std::string s = "C\rS";
    s.push_back(static_cast<char>('0' + *code));
    s += listen_only ? "\rL\r" : "\rO\r";
    return s;
}

bool slcan_parse_line(std::string_view line, SlcanEvent& out) {
    if (line.empty()) {
        out = SlcanEvent{};
        out.kind = SlcanEvent::Kind::Ok;
        return true;
    }
    if (line.size() > kSlcanMaxLine) return false;
    if (is_frame_letter(line[0])) return parse_frame(line, out);
    return parse_command(line, out);
}

void SlcanParser::reset() { line_.clear(); }

void SlcanParser::feed(std::string_view text, const EventFn& on_event) {
    feed(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()),
                                       text.size()),
         on_event);
}

void SlcanParser::finish_line(const EventFn& on_event) {
    SlcanEvent ev;
    if (slcan_parse_line(line_, ev)) {
        line_.clear();
        switch (ev.kind) {
            case SlcanEvent::Kind::Frame:
                ++counters_.frames;
                break;
            case SlcanEvent::Kind::Command:
                ++counters_.commands;
                break;
            case SlcanEvent::Kind::Ok:
                ++counters_.oks;
                break;
            case SlcanEvent::Kind::Error:
                ++counters_.errors;
                break;
        }
        on_event(ev);
        return;
    }
    // Resynchronise: garbage glued to the front of a frame line loses only the garbage.
    for (std::size_t i = 1; i < line_.size(); ++i) {
        if (!is_frame_letter(line_[i])) continue;
        if (slcan_parse_line(std::string_view(line_).substr(i), ev)) {
            counters_.garbage_bytes += i;
            ++counters_.frames;
            line_.clear();
            on_event(ev);
            return;
        }
    }
    ++counters_.malformed;
    counters_.garbage_bytes += line_.size() + 1;  // the terminator belonged to the bad line
    line_.clear();
}

void SlcanParser::feed(std::span<const std::uint8_t> bytes, const EventFn& on_event) {
    for (const std::uint8_t b : bytes) {
        const char c = static_cast<char>(b);
        if (c == kSlcanOk) {
            finish_line(on_event);
        } else if (c == kSlcanError) {
            // `\a` is a complete reply; a partial line before it was cut short.
            if (!line_.empty()) {
                counters_.garbage_bytes += line_.size();
                ++counters_.malformed;
                line_.clear();
            }
            ++counters_.errors;
            SlcanEvent ev;
            ev.kind = SlcanEvent::Kind::Error;
            on_event(ev);
        } else if (c == '\n' && line_.empty()) {
            // `\r\n` line ends from some firmwares: ignore the `\n`.
        } else {
            line_.push_back(c);
            if (line_.size() > kSlcanMaxLine) {
                // No valid line is this long: drop the front up to the next frame letter.
                std::size_t cut = 1;
                while (cut < line_.size() && !is_frame_letter(line_[cut])) ++cut;
                counters_.garbage_bytes += cut;
                line_.erase(0, cut);
            }
        }
    }
}

}  // namespace mirage::navcan
