// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace mirage::nmea {

// NMEA 0183 sentence layer (docs/nav-protocols.md §1): `$` tag `,` fields `*hh` CR LF.

// Longest sentence accepted, counting `$` and CR LF. The standard says 82; INS high-precision
// GGA exceeds it, so we accept up to 120 (§1).
inline constexpr std::size_t kMaxSentenceBytes = 120;
// Most fields any sentence we decode carries (RMC has 13); a line with more is still framed.
inline constexpr std::size_t kMaxFields = 40;

// The sentence types decoded, independent of the talker (GP, GN, GL, GA, GB, IN, HE, …).
enum class SentenceType : std::uint8_t { Unknown, Gga, Rmc, Vtg, Hdt, Zda, Pashr, PtnlAvr };

// XOR of every byte of `body` (the bytes strictly between `$` and `*`).
std::uint8_t checksum(std::string_view body);

// Outcome of framing one line, in the fixed validation order: length, sync, checksum, tag.
enum class FrameStatus : std::uint8_t {
    Ok,
    TooLong,      // more than kMaxSentenceBytes
    NoSync,       // does not start with `$`
    Truncated,    // no `*hh` at the end
    BadChecksum,  // `*hh` is not hex or does not match
    BadChar,      // non-printable byte, or more than kMaxFields fields
    BadTag,       // tag is not 2..5 upper-case letters/digits
};

// A framed sentence: views into the caller's line, valid while it lives.
struct Sentence {
    std::string_view tag;     // "GPGGA", "PASHR", "PTNL"
    std::string_view talker;  // "GP"; empty for proprietary tags (starting with 'P')
    SentenceType type = SentenceType::Unknown;
    std::array<std::string_view, kMaxFields> field{};  // field[0] is the first after the tag
    std::size_t count = 0;

    // Field i (0-based after the tag), or empty (= no data) past the end.
    std::string_view at(std::size_t i) const { return i < count ? field[i] : std::string_view{}; }
};

// Frames `line` ("$GPHDT,274.07,T*03", with or without trailing CR/LF) into `out`. Never throws.
FrameStatus parse_sentence(std::string_view line, Sentence& out);

// "$" + body + "*HH\r\n" with the checksum of body (two upper-case hex digits).
std::string frame_sentence(std::string_view body);

}  // namespace mirage::nmea
