// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/dis_uri.hpp"

#include <fmt/format.h>

#include "mirage/bytestream/uri_query.hpp"
#include "mirage/core/error.hpp"

namespace mirage::navio {
namespace {

constexpr const char* kComponent = "nav dis";

// "site.application.entity", each 0..65535.
dis::EntityId parse_entity(const std::string& uri, const std::string& text) {
    std::uint16_t v[3] = {0, 0, 0};
    std::size_t from = 0;
    for (int i = 0; i < 3; ++i) {
        const auto dot = i < 2 ? text.find('.', from) : text.size();
        const auto n = dot == std::string::npos
                           ? std::nullopt
                           : bytestream::parse_unsigned(text.substr(from, dot - from));
        if (!n || *n > 65535)
            throw ConfigError(
                fmt::format("{} '{}': entity='{}': expected site.application.entity, each 0..65535",
                            kComponent, uri, text));
        v[i] = static_cast<std::uint16_t>(*n);
        from = dot + 1;
    }
    return {v[0], v[1], v[2]};
}

}  // namespace

dis::TrackConfig parse_dis_transport(const std::string& transport, std::string& udp_uri) {
    const bytestream::UriQuery q = bytestream::parse_uri_query(kComponent, transport);
    q.check_keys(kComponent, transport, "exercise,entity,timeout");
    if (!q.head.starts_with("udp://"))
        throw ConfigError(
            fmt::format("{} '{}': DIS PDUs arrive as UDP datagrams: "
                        "expected udp://[bind]:port",
                        kComponent, transport));
    dis::TrackConfig c;
    if (const auto e = q.number(kComponent, transport, "exercise", 0, 255))
        c.filter.exercise = static_cast<std::uint8_t>(*e);
    if (q.has("entity")) c.filter.entity = parse_entity(transport, q.items.at("entity"));
    if (const auto t = q.number(kComponent, transport, "timeout", 1, 3600))
        c.timeout = std::chrono::seconds(*t);
    udp_uri = q.head;
    return c;
}

}  // namespace mirage::navio
