// SPDX-License-Identifier: Apache-2.0
// open_can_bus(): bus specs (can_bus.hpp) -> backends.
#include "mirage/can/can_bus.hpp"

#include <fmt/format.h>

#include <string_view>

#include "mirage/bytestream/uri_query.hpp"
#include "mirage/can/gsusb_bus.hpp"
#include "mirage/can/memory_bus.hpp"
#include "mirage/can/slcan_bus.hpp"
#include "mirage/can/socketcan_bus.hpp"
#include "mirage/core/error.hpp"

namespace mirage::can {
namespace {

constexpr std::string_view kComponent = "can bus";

[[noreturn]] void bad(const std::string& spec, const std::string& why) {
    throw ConfigError(fmt::format("{} '{}': {}", kComponent, spec, why));
}

bool flag(const bytestream::UriQuery& q, const std::string& spec, const std::string& key) {
    if (!q.has(key)) return false;
    const std::string& v = q.items.at(key);
    if (v.empty() || v == "1" || v == "true") return true;
    if (v == "0" || v == "false") return false;
    bad(spec, fmt::format("{}='{}': expected 1, 0, true or false", key, v));
}

// Exactly four hex digits ("1d50").
std::uint16_t hex16(const std::string& spec, std::string_view text, const char* what) {
    if (text.size() != 4) bad(spec, fmt::format("{} '{}': expected 4 hex digits", what, text));
    std::uint32_t v = 0;
    for (char c : text) {
        std::uint32_t d;
        if (c >= '0' && c <= '9')
            d = static_cast<std::uint32_t>(c - '0');
        else if (c >= 'a' && c <= 'f')
            d = static_cast<std::uint32_t>(c - 'a' + 10);
        else if (c >= 'A' && c <= 'F')
            d = static_cast<std::uint32_t>(c - 'A' + 10);
        else
            bad(spec, fmt::format("{} '{}': expected 4 hex digits", what, text));
        v = v * 16 + d;
    }
    return static_cast<std::uint16_t>(v);
}

std::unique_ptr<CanBus> open_slcan_spec(const std::string& spec) {
    const auto q = bytestream::parse_uri_query(kComponent, spec);
    q.check_keys(kComponent, spec, "baud,bitrate,listen");
    SlcanOptions o;
    o.device = q.head.substr(6);
    if (o.device.empty()) bad(spec, "no serial device (slcan:/dev/ttyACM0)");
    if (auto v = q.number(kComponent, spec, "baud", 1, 4'000'000)) o.baud = static_cast<std::uint32_t>(*v);
    if (auto v = q.number(kComponent, spec, "bitrate", 1, 1'000'000)) o.bitrate = static_cast<std::uint32_t>(*v);
    o.listen_only = flag(q, spec, "listen");
    try {
        return open_slcan(o);
    } catch (const ConfigError& e) {
        bad(spec, e.what());  // e.g. a baud termios does not know, or a bitrate without `Sn`
    }
}

std::unique_ptr<CanBus> open_gsusb_spec(const std::string& spec) {
    const auto q = bytestream::parse_uri_query(kComponent, spec);
    q.check_keys(kComponent, spec, "bitrate,serial,channel,listen");
    const std::string_view ids = std::string_view(q.head).substr(6);
    const auto colon = ids.find(':');
    GsUsbOptions o;
    if (colon == std::string_view::npos) bad(spec, "expected gsusb:<vid>:<pid> (hex)");
    o.vendor_id = hex16(spec, ids.substr(0, colon), "vendor id");
    o.product_id = hex16(spec, ids.substr(colon + 1), "product id");
    if (auto v = q.number(kComponent, spec, "bitrate", 1, 1'000'000)) o.bitrate = static_cast<std::uint32_t>(*v);
    if (auto v = q.number(kComponent, spec, "channel", 0, 255)) o.channel = static_cast<std::uint8_t>(*v);
    if (q.has("serial")) {
        o.serial = q.items.at("serial");
        if (o.serial.empty()) bad(spec, "serial= needs a value");
    }
    o.listen_only = flag(q, spec, "listen");
    return open_gsusb(o);
}

}  // namespace

std::unique_ptr<CanBus> open_can_bus(const std::string& spec) {
    const std::string_view s = spec;
    if (s.starts_with("socketcan:")) {
        const std::string ifname(s.substr(10));
        if (ifname.empty()) bad(spec, "no interface name (socketcan:can0)");
        if (ifname.find_first_of("?/ \t") != std::string::npos)
            bad(spec, fmt::format("'{}' is not an interface name", ifname));
        if (ifname.size() > 15) bad(spec, "interface names have at most 15 characters");
        return open_socketcan(ifname);
    }
    if (s.starts_with("slcan:")) return open_slcan_spec(spec);
    if (s.starts_with("gsusb:")) return open_gsusb_spec(spec);
    if (s.starts_with("memory:")) {
        const std::string name(s.substr(7));
        if (name.empty()) bad(spec, "no bus name (memory:bench)");
        if (name.find('?') != std::string::npos) bad(spec, "memory buses take no options");
        return open_memory_bus(name);
    }
    bad(spec, "unknown kind (expected socketcan:<ifname>, slcan:<device>, gsusb:<vid>:<pid> or "
              "memory:<name>)");
}

}  // namespace mirage::can
