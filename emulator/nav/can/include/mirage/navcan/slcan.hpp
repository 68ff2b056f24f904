// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "mirage/nav/can_frame.hpp"

// slcan / Lawicel ASCII line codec (docs/nav-protocols.md §9). Pure: no serial port here; the slcan
// CanBus backend (drivers/can) writes slcan_encode()/slcan_command_text() to its line and feeds
// what it reads to an SlcanParser. The same parser reads either direction of the line (host ->
// adapter commands and frames, adapter -> host frames and replies).
namespace mirage::navcan {

// Line terminators: `\r` ends every line and is also the bare OK reply; `\a` is the error reply.
inline constexpr char kSlcanOk = '\r';
inline constexpr char kSlcanError = '\a';
// Longest valid line without its `\r`: `T` + 8 id + 1 dlc + 16 data + 4 timestamp.
inline constexpr std::size_t kSlcanMaxLine = 30;

struct SlcanCommand {
    enum class Kind : std::uint8_t {
        SetBitrate,      // `Sn`, n = 0..8; `value` = n, `bitrate_bps` = the rate
        SetBtr,          // `sxxyy` SJA1000 BTR0/BTR1; `value` = 0xXXYY
        Open,            // `O`
        OpenListenOnly,  // `L`
        Close,           // `C`
        Status,          // `F` (request) or `Fxx` (reply, `value` = xx, `has_value`)
        Version,         // `V` (request) or `Vhhss` (reply, `value` = 0xhhss, `has_value`)
        SwVersion,       // `v` (request) or `vxxxx` (reply)
        Serial,          // `N` (request) or `Nxxxx` (reply, `text` = the 4 characters)
        Timestamps,      // `Z0` / `Z1`: `value` 0 off, 1 on
        TransmitAck,     // bare `z` / `Z`: Lawicel CANUSB acknowledging a transmitted frame
    };
    Kind kind = Kind::Open;
    std::uint32_t value = 0;
    bool has_value = false;
    std::uint32_t bitrate_bps = 0;  // SetBitrate only
    std::string text;               // argument characters after the command letter

    friend bool operator==(const SlcanCommand&, const SlcanCommand&) = default;
};

struct SlcanEvent {
    enum class Kind : std::uint8_t {
        Frame,    // `frame` (and `timestamp_ms` when the line carried a Z timestamp)
        Command,  // `command`
        Ok,       // a bare `\r`
        Error,    // `\a`
    };
    Kind kind = Kind::Ok;
    nav::CanFrame frame{};
    std::optional<std::uint16_t> timestamp_ms;  // 0..0xEA5F (0..59999 ms), wraps every minute
    SlcanCommand command{};
};

struct SlcanCounters {
    std::uint64_t frames = 0;
    std::uint64_t commands = 0;
    std::uint64_t oks = 0;
    std::uint64_t errors = 0;         // `\a` replies
    std::uint64_t malformed = 0;      // lines that were not a valid frame/command (or too long)
    std::uint64_t garbage_bytes = 0;  // bytes dropped while resynchronising
};

// Bitrate of `Sn` (10k, 20k, 50k, 100k, 125k, 250k, 500k, 800k, 1M); nullopt outside 0..8.
std::optional<std::uint32_t> slcan_bitrate_bps(int code);
// `n` of `Sn` for a bitrate in bit/s; nullopt when slcan has no code for it.
std::optional<int> slcan_bitrate_code(std::uint32_t bitrate_bps);

// `t1234DEADBEEF\r`, `T18FF50E58AABBCCDD11223344\r`, `r1230\r`, `R000001232\r`. With
// `timestamp_ms`, its 4 hex digits go before the `\r` (value taken modulo 60000). Hex is upper
// case. An error frame has no slcan form: returns "" (callers count it as not sent). An ID too
// wide for its format is masked (11 / 29 bits); len > 8 is sent as 8.
std::string slcan_encode(const nav::CanFrame& frame);
std::string slcan_encode(const nav::CanFrame& frame, std::uint16_t timestamp_ms);

// Text of a command including the trailing `\r`: "S6\r", "O\r", "C\r", "Z1\r", "V\r", "F\r".
// Reply forms (has_value) give "F00\r", "V1013\r", "N1234\r".
std::string slcan_command_text(const SlcanCommand& cmd);
// Convenience: the commands Linux slcand sends when it attaches (`C\rS6\rO\r` for 500 kbit/s),
// or "" if the bitrate has no `Sn` code.
std::string slcan_open_sequence(std::uint32_t bitrate_bps, bool listen_only = false);

// Parses one line without its terminator. false when the line is not a valid frame or
// command (the event is then unspecified). An empty line is an Ok event.
bool slcan_parse_line(std::string_view line, SlcanEvent& out);

// Incremental parser over the raw byte stream: any split of the input gives the same events.
// Lines end at `\r`; `\a` is an Error event on its own; `\n` between lines is ignored. A line
// that does not parse is dropped (malformed + its bytes as garbage) unless a valid frame starts
// inside it (garbage glued to the front of a frame), in which case the garbage prefix is
// counted and the frame delivered. A line growing past kSlcanMaxLine drops its front up to the
// next frame letter (memory stays bounded). Never throws (except from the callback), never
// reads out of bounds.
class SlcanParser {
  public:
    using EventFn = std::function<void(const SlcanEvent&)>;

    void feed(std::span<const std::uint8_t> bytes, const EventFn& on_event);
    void feed(std::string_view text, const EventFn& on_event);
    // Drops a partial line (e.g. after reopening the port).
    void reset();

    const SlcanCounters& counters() const { return counters_; }

  private:
    void finish_line(const EventFn& on_event);

    std::string line_;
    SlcanCounters counters_;
};

}  // namespace mirage::navcan
