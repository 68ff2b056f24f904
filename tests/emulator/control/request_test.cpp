// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/request.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace mirage::control {
namespace {

using Bytes = std::vector<std::uint8_t>;
constexpr std::size_t kIn = 140, kHold = 120;  // two sensors

Exception ex(const Bytes& b) { return check_request(b, kIn, kHold).exception; }

TEST(ControlRequest, ReadsWithinTheWindowPass) {
    const Checked c = check_request(Bytes{0x04, 0x00, 0x64, 0x00, 0x28}, kIn, kHold);
    ASSERT_EQ(c.exception, Exception::None);
    EXPECT_EQ(c.request.function, Function::ReadInput);
    EXPECT_EQ(c.request.address, 100);
    EXPECT_EQ(c.request.count, 40);
    EXPECT_EQ(ex({0x03, 0x00, 0x00, 0x00, 0x78}), Exception::None);  // 0..119
}

TEST(ControlRequest, FunctionThenLengthThenAddressThenCount) {
    EXPECT_EQ(ex({}), Exception::IllegalFunction);
    EXPECT_EQ(ex({0x01, 0x00, 0x00, 0x00, 0x01}), Exception::IllegalFunction);     // coils
    EXPECT_EQ(ex({0x07}), Exception::IllegalFunction);                             // short FC 07
    EXPECT_EQ(ex({0x11}), Exception::IllegalFunction);                             // short FC 11
    EXPECT_EQ(ex({0x03, 0x00, 0x00, 0x00}), Exception::IllegalValue);              // short
    EXPECT_EQ(ex({0x03, 0x00, 0x00, 0x00, 0x01, 0x00}), Exception::IllegalValue);  // padded
    EXPECT_EQ(ex({0x04, 0x00, 0x8B, 0x00, 0x02}), Exception::IllegalAddress);      // 139..140
    EXPECT_EQ(ex({0x04, 0x00, 0x00, 0x00, 0x00}), Exception::IllegalValue);        // count 0
    EXPECT_EQ(ex({0x04, 0x00, 0x00, 0x00, 0x7E}), Exception::IllegalValue);        // count 126
    EXPECT_EQ(ex({0x06, 0x00, 0x78, 0x00, 0x01}), Exception::IllegalAddress);      // 120
}

TEST(ControlRequest, WriteMultipleCountsAndByteCountsMustAgree) {
    const Checked c = check_request(
        Bytes{0x10, 0x00, 0x64, 0x00, 0x02, 0x04, 0x00, 0x0A, 0xFF, 0xFE}, kIn, kHold);
    ASSERT_EQ(c.exception, Exception::None);
    EXPECT_EQ(c.request.values[0], 10);
    EXPECT_EQ(c.request.values[1], 0xFFFE);
    // Byte count says 4, count says 3 (CVE-2019-14463's shape).
    EXPECT_EQ(ex({0x10, 0x00, 0x64, 0x00, 0x03, 0x04, 0x00, 0x0A, 0xFF, 0xFE}),
              Exception::IllegalValue);
    // Byte count larger than the bytes present.
    EXPECT_EQ(ex({0x10, 0x00, 0x64, 0x00, 0x02, 0x06, 0x00, 0x0A, 0xFF, 0xFE}),
              Exception::IllegalValue);
    // Count 124 with a matching byte count 248: over the function's maximum of 123.
    Bytes big{0x10, 0x00, 0x00, 0x00, 0x7C, 0xF8};
    big.resize(6 + 248);
    EXPECT_EQ(ex(big), Exception::IllegalValue);
}

}  // namespace
}  // namespace mirage::control
