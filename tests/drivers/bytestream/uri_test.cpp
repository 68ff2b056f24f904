// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/bytestream/uri_query.hpp"
#include "mirage/core/error.hpp"

namespace mirage::bytestream {
namespace {

// The message of the ConfigError thrown by open_byte_stream(uri), or "" when none was thrown.
std::string config_error(const std::string& uri) {
    try {
        open_byte_stream(uri);
    } catch (const ConfigError& e) {
        return e.what();
    } catch (const IoError&) {
        return "IoError";
    }
    return "";
}

TEST(ByteStreamUri, malformed_uris_are_config_errors_naming_the_uri) {
    struct Case {
        std::string uri, fragment;
    };
    const Case cases[] = {
        {"", "empty URI"},
        {"ftp://x:1", "unknown transport"},
        {"ttyUSB0", "unknown transport"},
        {"tcp://host", "expected host:port"},
        {"tcp://host:99999", "port '99999'"},
        {"tcp://host:0", "port other than 0"},
        {"tcp://:4000", "needs a host"},
        {"tcp://h:1?baud=9600", "unknown option 'baud'"},
        {"udp://::1:3000", "brackets"},
        {"udp://[::1:3000", "[ipv6-address]:port"},
        {"udp://:3000?send", "needs host and port"},
        {"udp://h:3000?send=1", "takes no value"},
        {"/dev/ttyS0?baud=12345", "baud=12345 has no termios speed"},
        {"/dev/ttyS0?baud=fast", "baud='fast'"},
        {"/dev/ttyS0?bits=9", "bits='9'"},
        {"/dev/ttyS0?parity=mark", "parity='mark'"},
        {"/dev/ttyS0?stop=3", "stop='3'"},
        {"/dev/ttyS0?speed=9600", "unknown option 'speed'"},
        {"/dev/ttyS0?baud=9600&baud=4800", "given twice"},
        {"/dev/ttyS0?=1", "empty option name"},
        {"serial:", "no device path"},
    };
    for (const auto& c : cases) {
        const std::string msg = config_error(c.uri);
        EXPECT_NE(msg.find("byte stream '" + c.uri + "'"), std::string::npos) << c.uri << ": " << msg;
        EXPECT_NE(msg.find(c.fragment), std::string::npos) << c.uri << ": " << msg;
    }
}

TEST(ByteStreamUri, open_failures_are_io_errors_naming_the_device) {
    try {
        open_byte_stream("/nonexistent/ttyX?baud=9600");
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("serial '/nonexistent/ttyX'"), std::string::npos)
            << e.what();
    }
    // A regular file is not a terminal.
    try {
        open_byte_stream("serial:/proc/self/status");
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("not a terminal"), std::string::npos) << e.what();
    }
}

TEST(UriQuery, splits_head_and_items_and_parses_numbers) {
    const UriQuery q = parse_uri_query("x", "slcan:/dev/a?baud=115200&bitrate=500000&listen");
    EXPECT_EQ(q.head, "slcan:/dev/a");
    ASSERT_EQ(q.items.size(), 3u);
    EXPECT_EQ(q.items.at("listen"), "");
    EXPECT_EQ(q.number("x", "u", "baud", 1, 4'000'000).value(), 115200u);
    EXPECT_FALSE(q.number("x", "u", "absent", 0, 1).has_value());
    EXPECT_THROW(q.number("x", "u", "bitrate", 0, 1000), ConfigError);
    EXPECT_NO_THROW(q.check_keys("x", "u", "baud,bitrate,listen"));
    EXPECT_THROW(q.check_keys("x", "u", "baud,bitrate"), ConfigError);
    EXPECT_EQ(parse_unsigned("18446744073709551615").value(), 18446744073709551615ull);
    EXPECT_FALSE(parse_unsigned("18446744073709551616").has_value());
    EXPECT_FALSE(parse_unsigned("+1").has_value());
    EXPECT_FALSE(parse_unsigned("").has_value());
}

}  // namespace
}  // namespace mirage::bytestream
