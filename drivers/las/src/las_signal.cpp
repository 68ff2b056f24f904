// SPDX-License-Identifier: Apache-2.0
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>

#include "mirage/las/las_writer.hpp"
#include "signal_registry.hpp"

namespace mirage::las {
namespace {

// A fixed table of lock-free atomics: the handler may neither lock nor allocate.
constexpr std::size_t kMaxWriters = 64;
std::array<std::atomic<LasWriter*>, kMaxWriters> g_writers{};
static_assert(std::atomic<LasWriter*>::is_always_lock_free);

extern "C" void finalize_and_reraise(int sig) {
    const int saved_errno = errno;
    for (auto& slot : g_writers) {
        if (LasWriter* w = slot.load(std::memory_order_acquire)) w->finalize_for_signal();
    }
    // Default action, then re-raise: the signal is blocked while this handler runs, so it is
    // delivered (and terminates the process with the right status) as soon as we return.
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, nullptr);
    raise(sig);
    errno = saved_errno;
}

}  // namespace

namespace detail {

bool register_writer(LasWriter* w) noexcept {
    for (auto& slot : g_writers) {
        LasWriter* expected = nullptr;
        if (slot.compare_exchange_strong(expected, w, std::memory_order_acq_rel)) return true;
    }
    return false;
}

void unregister_writer(LasWriter* w) noexcept {
    for (auto& slot : g_writers) {
        LasWriter* expected = w;
        if (slot.compare_exchange_strong(expected, nullptr, std::memory_order_acq_rel)) return;
    }
}

}  // namespace detail

void install_signal_finalizer() {
    struct sigaction sa {};
    sa.sa_handler = finalize_and_reraise;
    sigemptyset(&sa.sa_mask);
    // Block both while one is handled, so a SIGTERM cannot interrupt a SIGINT finalisation.
    sigaddset(&sa.sa_mask, SIGINT);
    sigaddset(&sa.sa_mask, SIGTERM);
    sa.sa_flags = 0;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

}  // namespace mirage::las
