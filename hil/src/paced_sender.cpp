// SPDX-License-Identifier: Apache-2.0
#include "paced_sender.hpp"

#include <cstdio>

namespace mirage::hil {

std::shared_ptr<udp::SharedSender> make_paced_sender(int rt_priority,
                                                     const hostclock::KeepAwake* awake,
                                                     const char* command) {
    udp::SharedSenderConfig sc;
    sc.fifo_priority = rt_priority;
    sc.cpu = hostclock::sending_cpu_of(awake);
    auto sender = std::make_shared<udp::SharedSender>(sc);
    if ((rt_priority > 0 && !sender->fifo()) || (awake && !sender->fifo_error().empty()))
        std::fprintf(stderr, "mirage %s: sender: %s\n", command, sender->fifo_error().c_str());
    return sender;
}

}  // namespace mirage::hil
