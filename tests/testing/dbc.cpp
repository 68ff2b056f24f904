// SPDX-License-Identifier: Apache-2.0
#include "dbc.hpp"

#include <charconv>
#include <fstream>
#include <sstream>

#include "mirage/core/error.hpp"

namespace mirage::navcan {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

// Splits off the text before `delim` (trimmed); false if `delim` is absent.
bool take_until(std::string_view& s, char delim, std::string_view& head) {
    const std::size_t p = s.find(delim);
    if (p == std::string_view::npos) return false;
    head = trim(s.substr(0, p));
    s.remove_prefix(p + 1);
    return true;
}

template <class T>
bool to_number(std::string_view s, T& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc{} && r.ptr == s.data() + s.size();
}

// ` name [mux] : 0|16@1- (0.01,0) [-327.68|327.67] "m/s" receivers`
bool parse_signal(std::string_view s, DbcSignal& sig) {
    std::string_view head;
    if (!take_until(s, ':', head) || head.empty()) return false;
    const std::size_t sp = head.find_first_of(" \t");
    sig.name = std::string(head.substr(0, sp));  // a multiplexer mark after the name is ignored
    std::string_view v;
    if (!take_until(s, '|', v) || !to_number(v, sig.start_bit)) return false;
    if (!take_until(s, '@', v) || !to_number(v, sig.length)) return false;
    s = trim(s);
    if (s.size() < 2 || (s[0] != '0' && s[0] != '1') || (s[1] != '+' && s[1] != '-')) return false;
    sig.little_endian = s[0] == '1';
    sig.is_signed = s[1] == '-';
    s.remove_prefix(2);
    if (!take_until(s, '(', v) || !v.empty()) return false;
    if (!take_until(s, ',', v) || !to_number(v, sig.factor)) return false;
    if (!take_until(s, ')', v) || !to_number(v, sig.offset)) return false;
    if (!take_until(s, '[', v) || !v.empty()) return false;
    if (!take_until(s, '|', v) || !to_number(v, sig.minimum)) return false;
    if (!take_until(s, ']', v) || !to_number(v, sig.maximum)) return false;
    if (!take_until(s, '"', v) || !v.empty()) return false;
    if (!take_until(s, '"', v)) return false;
    sig.unit = std::string(v);
    return sig.length >= 1 && sig.length <= 64;
}

// `BO_ 1536 DateTime: 8 RT`
bool parse_message(std::string_view s, DbcMessage& msg) {
    std::string_view v;
    s = trim(s);
    const std::size_t sp = s.find_first_of(" \t");
    if (sp == std::string_view::npos) return false;
    std::uint64_t id = 0;
    if (!to_number(s.substr(0, sp), id) || id > 0xFFFF'FFFFu) return false;
    s.remove_prefix(sp);
    if (!take_until(s, ':', v) || v.empty()) return false;
    msg.name = std::string(v);
    s = trim(s);
    const std::size_t sp2 = s.find_first_of(" \t");
    if (!to_number(s.substr(0, sp2), msg.dlc)) return false;
    msg.extended = (id & 0x8000'0000u) != 0;
    msg.id = static_cast<std::uint32_t>(id & 0x1FFF'FFFFu);
    return true;
}

}  // namespace

std::optional<double> DbcSignal::decode(const nav::CanFrame& frame) const {
    if (!little_endian || length == 0 || start_bit + length > 8u * frame.len) return std::nullopt;
    // Bit by bit, on purpose unlike the codecs' word-wise extraction, so the check is independent.
    std::uint64_t raw = 0;
    for (unsigned i = 0; i < length; ++i) {
        const unsigned bit = start_bit + i;
        raw |= static_cast<std::uint64_t>((frame.data[bit / 8] >> (bit % 8)) & 1u) << i;
    }
    if (is_signed && length < 64 && ((raw >> (length - 1)) & 1u) != 0)
        return static_cast<double>(
                   static_cast<std::int64_t>(raw | ~((std::uint64_t{1} << length) - 1))) *
                   factor +
               offset;
    return static_cast<double>(raw) * factor + offset;
}

const DbcSignal* DbcMessage::signal(std::string_view n) const {
    for (const auto& s : signals) {
        if (s.name == n) return &s;
    }
    return nullptr;
}

const DbcMessage* Dbc::message(std::uint32_t id, bool extended) const {
    for (const auto& m : messages_) {
        if (m.id == id && m.extended == extended) return &m;
    }
    return nullptr;
}

const DbcMessage* Dbc::message(std::string_view name) const {
    for (const auto& m : messages_) {
        if (m.name == name) return &m;
    }
    return nullptr;
}

Dbc Dbc::parse(std::string_view text, const std::string& name) {
    Dbc dbc;
    std::size_t line_no = 0;
    while (!text.empty()) {
        const std::size_t nl = text.find('\n');
        const std::string_view line = text.substr(0, nl);
        text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
        ++line_no;
        const std::string_view t = trim(line);
        auto fail = [&](const char* what) {
            throw ConfigError("dbc '" + name + "': line " + std::to_string(line_no) + ": " + what);
        };
        if (t.starts_with("BO_ ")) {
            DbcMessage m;
            if (!parse_message(t.substr(4), m)) fail("malformed BO_ line");
            dbc.messages_.push_back(std::move(m));
        } else if (t.starts_with("SG_ ")) {
            if (dbc.messages_.empty()) fail("SG_ before any BO_");
            DbcSignal sig;
            if (!parse_signal(t.substr(4), sig)) fail("malformed SG_ line");
            dbc.messages_.back().signals.push_back(std::move(sig));
        }
    }
    return dbc;
}

Dbc Dbc::load(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("dbc '" + path.string() + "': cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parse(ss.str(), path.string());
}

}  // namespace mirage::navcan
