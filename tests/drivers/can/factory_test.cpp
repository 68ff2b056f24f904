// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <string>

#include "mirage/can/can_bus.hpp"
#include "mirage/core/error.hpp"

namespace mirage::can {
namespace {

std::string config_error(const std::string& spec) {
    try {
        open_can_bus(spec);
    } catch (const ConfigError& e) {
        return e.what();
    } catch (const IoError& e) {
        return std::string("IoError: ") + e.what();
    }
    return "";
}

TEST(CanBusFactory, bad_specs_are_config_errors_naming_the_spec) {
    struct Case {
        std::string spec, fragment;
    };
    const Case cases[] = {
        {"", "unknown kind"},
        {"can0", "unknown kind"},
        {"vcan:can0", "unknown kind"},
        {"socketcan:", "no interface name"},
        {"socketcan:averyveryverylongname0", "at most 15"},
        {"socketcan:can0?bitrate=500000", "not an interface name"},
        {"slcan:", "no serial device"},
        {"slcan:/dev/x?bitrate=fast", "bitrate='fast'"},
        {"slcan:/dev/x?bitrate=2000000", "bitrate='2000000'"},
        {"slcan:/dev/x?bitrate=33333", "no slcan code"},
        {"slcan:/dev/x?speed=1", "unknown option 'speed'"},
        {"slcan:/dev/x?listen=maybe", "listen='maybe'"},
        {"gsusb:", "expected gsusb:<vid>:<pid>"},
        {"gsusb:1d50", "expected gsusb:<vid>:<pid>"},
        {"gsusb:1d5:606f", "vendor id '1d5'"},
        {"gsusb:1d50:60zf", "product id '60zf'"},
        {"gsusb:1d50:606f?bitrate=abc", "bitrate='abc'"},
        {"gsusb:1d50:606f?channel=256", "channel='256'"},
        {"gsusb:1d50:606f?serial=", "serial= needs a value"},
        {"gsusb:1d50:606f?bogus=1", "unknown option 'bogus'"},
        {"memory:", "no bus name"},
        {"memory:x?y=1", "no options"},
    };
    for (const auto& c : cases) {
        const std::string msg = config_error(c.spec);
        EXPECT_EQ(msg.rfind("can bus '" + c.spec + "'", 0), 0u) << c.spec << " -> " << msg;
        EXPECT_NE(msg.find(c.fragment), std::string::npos) << c.spec << " -> " << msg;
    }
}

TEST(CanBusFactory, slcan_on_a_missing_device_is_an_io_error_naming_it) {
    try {
        open_can_bus("slcan:/nonexistent/ttyACM9?baud=115200&bitrate=250000");
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/ttyACM9"), std::string::npos)
            << e.what();
    }
}

TEST(CanBusFactory, memory_spec_opens_a_memory_bus) {
    auto bus = open_can_bus("memory:factory");
    EXPECT_EQ(bus->name(), "memory:factory");
}

}  // namespace
}  // namespace mirage::can
