// SPDX-License-Identifier: Apache-2.0
#include "stop_signal.hpp"

#include <unistd.h>

#include <csignal>

namespace mirage::hil {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_stop_signal(int sig) {
    if (g_stop.exchange(true)) _exit(128 + sig);  // second signal: the user insists
}

}  // namespace

const std::atomic<bool>& install_stop_signal() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    return g_stop;
}

}  // namespace mirage::hil
