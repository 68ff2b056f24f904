// SPDX-License-Identifier: Apache-2.0
// open_socketcan's errors. Runs on the host (label unit) and again inside the CAN VM, where the
// kernel has AF_CAN and the "no such interface" branch is reached.
#include <gtest/gtest.h>
#include <linux/can.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <string>

#include "mirage/can/socketcan_bus.hpp"
#include "mirage/core/error.hpp"

namespace {

// True when this kernel offers raw CAN sockets (false on most CI containers).
bool kernel_has_af_can() {
    const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) return errno != EAFNOSUPPORT;
    ::close(fd);
    return true;
}

template <class E>
std::string message_of(const std::string& ifname) {
    try {
        (void)mirage::can::open_socketcan(ifname);
    } catch (const E& e) {
        return e.what();
    }
    return "<no exception>";
}

}  // namespace

TEST(SocketCanOpen, missing_af_can_or_missing_interface_is_an_io_error_naming_errno) {
    if (!kernel_has_af_can()) {
        EXPECT_EQ(message_of<mirage::IoError>("can0"),
                  "socketcan 'can0': this kernel has no AF_CAN: socket(PF_CAN, SOCK_RAW, CAN_RAW) "
                  "failed: Address family not supported by protocol (EAFNOSUPPORT); load the can "
                  "and can-raw modules, or use slcan: or gsusb:");
    } else {
        EXPECT_EQ(message_of<mirage::IoError>("nosuchcan7"),
                  "socketcan 'nosuchcan7': no such interface: No such device (ENODEV)");
    }
}

TEST(SocketCanOpen, interface_name_outside_1_to_15_characters_is_a_config_error) {
    EXPECT_EQ(message_of<mirage::ConfigError>(""),
              "socketcan '': an interface name has 1 to 15 characters");
    EXPECT_EQ(message_of<mirage::ConfigError>("abcdefghijklmnop"),
              "socketcan 'abcdefghijklmnop': an interface name has 1 to 15 characters");
}

TEST(SocketCanOpen, non_can_interface_is_refused_at_bind) {
    if (!kernel_has_af_can()) GTEST_SKIP() << "this kernel has no AF_CAN (runs in the CAN VM)";
    EXPECT_EQ(message_of<mirage::IoError>("lo"),
              "socketcan 'lo': bind failed: No such device (ENODEV) (is it a CAN interface?)");
}
