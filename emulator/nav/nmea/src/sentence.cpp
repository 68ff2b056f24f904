// SPDX-License-Identifier: Apache-2.0
#include "mirage/nmea/sentence.hpp"

namespace mirage::nmea {
namespace {

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;  // lenient: some talkers print lower case
    return -1;
}

bool is_tag_char(char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }

SentenceType standard_type(std::string_view t) {
    if (t == "GGA") return SentenceType::Gga;
    if (t == "RMC") return SentenceType::Rmc;
    if (t == "VTG") return SentenceType::Vtg;
    if (t == "HDT") return SentenceType::Hdt;
    if (t == "ZDA") return SentenceType::Zda;
    return SentenceType::Unknown;
}

}  // namespace

std::uint8_t checksum(std::string_view body) {
    std::uint8_t x = 0;
    for (char c : body) x = static_cast<std::uint8_t>(x ^ static_cast<std::uint8_t>(c));
    return x;
}

FrameStatus parse_sentence(std::string_view line, Sentence& out) {
    out = Sentence{};
    while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
    if (line.size() + 2 > kMaxSentenceBytes) return FrameStatus::TooLong;
    if (line.empty() || line.front() != '$') return FrameStatus::NoSync;
    const std::size_t star = line.rfind('*');
    if (star == std::string_view::npos || star + 3 != line.size()) return FrameStatus::Truncated;
    const int hi = hex_value(line[star + 1]);
    const int lo = hex_value(line[star + 2]);
    const std::string_view body = line.substr(1, star - 1);
    if (hi < 0 || lo < 0 || checksum(body) != hi * 16 + lo) return FrameStatus::BadChecksum;

    // Fields: printable ASCII only; `$`, `*` and `!` are delimiters, never data.
    std::size_t start = 0;
    bool first = true;
    for (std::size_t i = 0; i <= body.size(); ++i) {
        if (i < body.size()) {
            const char c = body[i];
            if (c < 0x20 || c > 0x7e || c == '$' || c == '*' || c == '!') {
                return FrameStatus::BadChar;
            }
            if (c != ',') continue;
        }
        const std::string_view f = body.substr(start, i - start);
        if (first) {
            out.tag = f;
            first = false;
        } else {
            if (out.count == kMaxFields) return FrameStatus::BadChar;
            out.field[out.count++] = f;
        }
        start = i + 1;
    }
    if (out.tag.size() < 2 || out.tag.size() > 5) return FrameStatus::BadTag;
    for (char c : out.tag) {
        if (!is_tag_char(c)) return FrameStatus::BadTag;
    }
    if (out.tag.front() == 'P') {
        // Proprietary: 'P' + maker code; the type is the rest of the tag or a field.
        if (out.tag == "PASHR") out.type = SentenceType::Pashr;
        if (out.tag == "PTNL" && out.at(0) == "AVR") out.type = SentenceType::PtnlAvr;
    } else if (out.tag.size() == 5) {
        out.talker = out.tag.substr(0, 2);
        out.type = standard_type(out.tag.substr(2));
    }
    return FrameStatus::Ok;
}

std::string frame_sentence(std::string_view body) {
    static constexpr char kHex[] = "0123456789ABCDEF";
    const std::uint8_t c = checksum(body);
    std::string s;
    s.reserve(body.size() + 6);
    s += '$';
    s += body;
    s += '*';
    s += kHex[c >> 4];
    s += kHex[c & 0x0f];
    s += "\r\n";
    return s;
}

}  // namespace mirage::nmea
