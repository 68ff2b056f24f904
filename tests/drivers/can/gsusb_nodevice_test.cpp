// SPDX-License-Identifier: Apache-2.0
// Opening a gs_usb adapter that is not there (no umockdev; the machine's real USB, if any).
#include <gtest/gtest.h>

#include "mirage/can/gsusb_bus.hpp"
#include "mirage/core/error.hpp"

namespace {

TEST(GsUsbNoDevice, missing_vid_pid_is_io_error_naming_the_device) {
    mirage::can::GsUsbOptions o;  // 1d50:606f
    try {
        mirage::can::open_gsusb(o);
        GTEST_SKIP() << "a real gs_usb adapter 1d50:606f is attached; nothing to test here";
    } catch (const mirage::IoError& e) {
        const std::string msg = e.what();
        // Either enumeration found nothing, or there is no usbfs at all (libusb_init fails).
        EXPECT_EQ(msg.rfind("gsusb 1d50:606f: no such device", 0), 0u) << msg;
    }
}

}  // namespace
