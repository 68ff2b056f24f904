// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/nav/can_frame.hpp"

// A minimal DBC reader: BO_ and SG_ lines only (start bit, length, byte order, sign,
// factor/offset incl. scientific notation such as 1E-007, unit). Files may be latin-1 (SBG's
// `°`, `µ`): bytes are kept as they are. The codecs use fixed tables; this reader is how the
// tests check every encoded signal against the vendors' (or our transcribed) databases.
namespace mirage::navcan {

struct DbcSignal {
    std::string name;
    unsigned start_bit = 0;
    unsigned length = 0;
    bool little_endian = true;  // @1 Intel; @0 Motorola (parsed, not decoded)
    bool is_signed = false;
    double factor = 1.0;
    double offset = 0.0;
    double minimum = 0.0;
    double maximum = 0.0;
    std::string unit;  // raw bytes from the file

    // Physical value of this signal in a frame; nullopt for Motorola signals or when the
    // signal does not fit in the frame's len bytes.
    std::optional<double> decode(const nav::CanFrame& frame) const;
};

struct DbcMessage {
    std::uint32_t id = 0;   // without the extended flag
    bool extended = false;  // bit 31 set in the DBC's BO_ id
    std::string name;
    unsigned dlc = 0;
    std::vector<DbcSignal> signals;

    const DbcSignal* signal(std::string_view name) const;
};

class Dbc {
  public:
    // Throws mirage::IoError (cannot read) or ConfigError ("dbc 'f.dbc': line 12: ...").
    static Dbc load(const std::filesystem::path& path);
    static Dbc parse(std::string_view text, const std::string& name = "<text>");

    const std::vector<DbcMessage>& messages() const { return messages_; }
    const DbcMessage* message(std::uint32_t id, bool extended = false) const;
    const DbcMessage* message(std::string_view name) const;

  private:
    std::vector<DbcMessage> messages_;
};

}  // namespace mirage::navcan
